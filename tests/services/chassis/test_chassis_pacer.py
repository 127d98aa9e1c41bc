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


@pytest.mark.parametrize(("speed", "caught_up"), [(1.0, True), (10.0, False)])
def test_the_catch_up_bound_is_sim_time(speed: float, caught_up: bool) -> None:
    """A 50 ms stall is 0.05 s of sim time at 1x (caught up: within 0.1 s) but 0.5 s at 10x
    (more than 0.1 s of robot time with no control tick: the schedule restarts instead)."""
    wall = FakeWall()
    p = Pacer(0.02, speed, clock=wall, max_lag=0.1)
    p.stepped()
    wall.t += p.period + 0.05
    assert p.delay() == 0.0  # due now either way
    p.stepped()
    assert (p.delay() == 0.0) is caught_up  # still behind: catching up; else on schedule


def test_unthrottled() -> None:
    p = Pacer(0.02, 0.0)
    assert p.period == 0.0 and p.delay() == 0.0
    with pytest.raises(ValueError):
        Pacer(0.0, 1.0)
