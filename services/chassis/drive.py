"""Drive: a simulated differential-drive base's velocity controller (limits, dead-man, e-stop).

`Drive.step(now, dt)` returns the velocities the base has over the next ``dt``: the last
command clamped to the velocity limits, reached under the acceleration limits, zero once
no command came for ``cmd_timeout`` seconds (the dead-man), and zero at once while the
latched e-stop is engaged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["CommandError", "Drive", "DriveLimits"]


class CommandError(ValueError):
    """A velocity command the base refuses (not finite, or far beyond any sane speed)."""


@dataclass(frozen=True)
class DriveLimits:
    """Velocity (m/s, rad/s) and acceleration (m/s², rad/s²) limits and the dead-man time.

    Commands beyond ``max_*`` are clamped; beyond ``refuse_factor`` times them they are
    refused as garbage.
    """

    max_linear: float = 1.0
    max_reverse: float = 0.3
    max_angular: float = 1.5
    max_linear_accel: float = 1.0
    max_linear_decel: float = 2.0
    max_angular_accel: float = 3.0
    cmd_timeout: float = 0.5
    refuse_factor: float = 10.0

    def __post_init__(self) -> None:
        for name in ("max_linear", "max_reverse", "max_angular", "max_linear_accel",
                     "max_linear_decel", "max_angular_accel", "cmd_timeout", "refuse_factor"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"{name} must be a finite number >= 0, got {v}")


def _approach(value: float, target: float, up: float, down: float) -> float:
    """Move ``value`` toward ``target`` by at most ``up`` when speeding up, ``down`` when
    slowing down (or reversing)."""
    if value * target < 0:  # reversing: slow down to zero first
        return max(value - down, 0.0) if value > 0 else min(value + down, 0.0)
    if abs(target) > abs(value):
        step = up
    else:
        step = down
    if target > value:
        return min(value + step, target)
    return max(value - step, target)


class Drive:
    """The base's velocity state; commands and steps are stamped in seconds of sim time."""

    def __init__(self, limits: DriveLimits) -> None:
        self.limits = limits
        self.linear = 0.0
        self.angular = 0.0
        self.estop = False
        self.held_by: str | None = None  # who drives the base instead of cmd_vel (`hold`)
        self._cmd = (0.0, 0.0)
        self._cmd_time: float | None = None

    def hold(self, owner: str | None) -> None:
        """``owner`` (e.g. a calibration) drives the base from now on, and ``cmd_vel`` is
        dropped until ``hold(None)``; either way the base stops first."""
        self.held_by = owner
        self.halt()

    def command(self, linear: float, angular: float, now: float) -> tuple[float, float]:
        """Take a velocity command; return it as clamped.

        Raises:
            CommandError: a non-finite value, or one beyond ``refuse_factor`` x the limit;
                the base then stops (the previous command is dropped).
        """
        lim = self.limits
        if not (math.isfinite(linear) and math.isfinite(angular)):
            self.halt()
            raise CommandError(f"non-finite velocity command ({linear}, {angular})")
        if (abs(linear) > lim.refuse_factor * max(lim.max_linear, lim.max_reverse, 0.1)
                or abs(angular) > lim.refuse_factor * max(lim.max_angular, 0.1)):
            self.halt()
            raise CommandError(f"velocity command ({linear:g} m/s, {angular:g} rad/s) is far "
                               f"beyond the limits ({lim.max_linear:g} m/s, "
                               f"{lim.max_angular:g} rad/s)")
        v = min(max(linear, -lim.max_reverse), lim.max_linear)
        w = min(max(angular, -lim.max_angular), lim.max_angular)
        self._cmd = (v, w)
        self._cmd_time = now
        return v, w

    def halt(self) -> None:
        """Drop the current command: the base decelerates to a stop under its limits."""
        self._cmd = (0.0, 0.0)
        self._cmd_time = None

    def stop_now(self) -> None:
        """Stop at once (contact, teleport): zero velocity and no command."""
        self.halt()
        self.linear = self.angular = 0.0

    def set_estop(self, engaged: bool) -> None:
        """Engage (stops at once and holds) or release the e-stop; releasing needs a new
        command before the base moves again."""
        self.estop = engaged
        self.stop_now()

    def timed_out(self, now: float) -> bool:
        """True when no command is in force (none yet, or the last is older than the dead-man)."""
        return self._cmd_time is None or now - self._cmd_time > self.limits.cmd_timeout

    def step(self, now: float, dt: float) -> tuple[float, float]:
        """Advance the velocities by ``dt`` toward the command in force at ``now``."""
        if self.estop:
            self.linear = self.angular = 0.0
            return 0.0, 0.0
        v, w = (0.0, 0.0) if self.timed_out(now) else self._cmd
        if not (v or w or self.linear or self.angular):  # at rest, and asked to stay
            return 0.0, 0.0
        lim = self.limits
        self.linear = _approach(self.linear, v, lim.max_linear_accel * dt,
                                lim.max_linear_decel * dt)
        self.angular = _approach(self.angular, w, lim.max_angular_accel * dt,
                                 lim.max_angular_accel * dt)
        return self.linear, self.angular
