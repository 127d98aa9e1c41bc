"""Pacer: steps at speed x real time, slows down instead of bursting, reports the factor."""

from __future__ import annotations

import pytest
from zenros.services.chassis.pacer import Pacer


class FakeWall:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_schedule_at_ten_times_real_time() -> None:
    wall = FakeWall()
    p = Pacer(0.02, 10.0, clock=wall)
    assert p.period == pytest.approx(0.002)
    assert p.delay() == 0.0
    p.stepped()
    assert p.delay() == pytest.approx(0.002)
    for _ in range(100):
        wall.t += p.delay()
        p.stepped()
    assert p.factor == pytest.approx(10.0)


def test_falls_behind_then_restarts_the_schedule_without_a_burst() -> None:
    wall = FakeWall()
    p = Pacer(0.02, 10.0, clock=wall, max_lag=0.1)
    for _ in range(10):
        wall.t += p.delay() + 0.004  # each step costs 4 ms: only 5x is possible
        p.stepped()
    assert p.factor == pytest.approx(5.0)
    wall.t += 0.5  # a long stall
    assert p.delay() == 0.0  # re-anchored at now
    p.stepped()
    assert p.delay() == pytest.approx(0.002)  # back to the normal period, no catch-up burst


def test_unthrottled() -> None:
    p = Pacer(0.02, 0.0)
    assert p.period == 0.0 and p.delay() == 0.0
    with pytest.raises(ValueError):
        Pacer(0.0, 1.0)
