"""Drive: velocity and acceleration limits, the dead-man timeout, e-stop, refused commands."""

from __future__ import annotations

import math

import pytest
from zenros.services.chassis.drive import CommandError, Drive, DriveLimits

DT = 0.02


def run(drive: Drive, t0: float, seconds: float) -> tuple[float, float]:
    n = round(seconds / DT)
    for i in range(n):
        drive.step(t0 + i * DT, DT)
    return drive.linear, drive.angular


def test_accelerates_within_limits_to_the_clamped_command() -> None:
    d = Drive(DriveLimits(max_linear=1.0, max_linear_accel=1.0, max_angular=1.5,
                          max_angular_accel=3.0))
    assert d.command(5.0, -9.0, 0.0) == (1.0, -1.5)  # clamped, not refused
    d.step(0.0, DT)
    assert d.linear == pytest.approx(0.02) and d.angular == pytest.approx(-0.06)
    v, w = run(d, DT, 0.28)
    assert v == pytest.approx(0.3) and w == pytest.approx(-0.9)
    d.command(5.0, -9.0, 0.3)
    v, w = run(d, 0.3, 0.2)
    assert v <= 1.0 and w == pytest.approx(-1.5)


def test_decelerates_and_reverses_through_zero() -> None:
    d = Drive(DriveLimits(max_linear_accel=1.0, max_linear_decel=2.0, max_reverse=0.3,
                          cmd_timeout=5.0))
    d.linear = 1.0
    d.command(-1.0, 0.0, 0.0)  # reverse clamped to 0.3
    d.step(0.0, DT)
    assert d.linear == pytest.approx(0.96)  # braking at 2 m/s^2
    run(d, DT, 0.5)  # stopped after 0.5 s, then reversing at 1 m/s^2
    assert -0.03 <= d.linear <= 0.0
    run(d, 0.52, 0.5)
    assert d.linear == pytest.approx(-0.3)


def test_dead_man_stops_after_half_a_second() -> None:
    d = Drive(DriveLimits(cmd_timeout=0.5, max_linear_decel=100.0))
    assert d.timed_out(0.0)
    d.command(0.5, 0.0, 0.0)
    run(d, 0.0, 0.48)
    assert d.linear == pytest.approx(0.48) and not d.timed_out(0.48)
    d.step(0.49, DT)
    assert d.linear > 0
    d.step(0.52, DT)  # 0.52 s after the last command
    assert d.linear == 0.0 and d.timed_out(0.52)


def test_estop_stops_at_once_and_holds_until_released_and_commanded() -> None:
    d = Drive(DriveLimits())
    d.command(0.5, 0.5, 0.0)
    run(d, 0.0, 0.3)
    d.set_estop(True)
    assert (d.linear, d.angular) == (0.0, 0.0)
    for i in range(20):
        d.command(0.5, 0.5, 0.3 + i * DT)
        assert d.step(0.3 + i * DT, DT) == (0.0, 0.0)
    d.set_estop(False)
    assert d.step(0.8, DT) == (0.0, 0.0)  # the old command is gone
    d.command(0.5, 0.0, 0.8)
    assert d.step(0.8, DT)[0] > 0


@pytest.mark.parametrize(("v", "w", "match"), [
    (math.nan, 0.0, "non-finite"),
    (0.0, math.inf, "non-finite"),
    (1e6, 0.0, "far beyond the limits"),
    (0.0, -400.0, "far beyond the limits"),
])
def test_garbage_commands_are_refused_and_stop_the_base(v: float, w: float, match: str) -> None:
    d = Drive(DriveLimits(max_linear_decel=100.0, max_angular_accel=100.0))
    d.command(0.5, 0.2, 0.0)
    run(d, 0.0, 0.2)
    with pytest.raises(CommandError, match=match):
        d.command(v, w, 0.2)
    d.step(0.22, DT)
    assert (d.linear, d.angular) == (0.0, 0.0)


def test_bad_limits_are_refused() -> None:
    with pytest.raises(ValueError, match="max_linear must be a finite number >= 0"):
        DriveLimits(max_linear=-1.0)
