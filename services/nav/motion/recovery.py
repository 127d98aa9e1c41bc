"""Recoveries: wait, back up and spin, as Nav2's behaviour server runs them when stuck.

Each is a small tick-driven state: `tick(sense)` returns (v, ω) and sets ``done``.
Backing up stops early if the scan shows something behind within the robot's radius.
"""

from __future__ import annotations

import math

from zenros.se2 import Pose2, angle_diff

from .behavior import Sense
from .collision import first_collision

__all__ = ["BackUp", "Recovery", "Spin", "Wait", "recovery_cycle"]


class Recovery:
    name = "recovery"

    def __init__(self) -> None:
        self.done = False
        self._start: Pose2 | None = None
        self._t0: float | None = None

    def begin(self, sense: Sense) -> None:
        if self._t0 is None:
            self._t0, self._start = sense.now, sense.pose

    def tick(self, sense: Sense) -> tuple[float, float]:
        raise NotImplementedError


class Wait(Recovery):
    name = "wait"

    def __init__(self, duration: float) -> None:
        super().__init__()
        self.duration = duration

    def tick(self, sense: Sense) -> tuple[float, float]:
        self.begin(sense)
        assert self._t0 is not None
        if sense.now - self._t0 >= self.duration:
            self.done = True
        return 0.0, 0.0


class BackUp(Recovery):
    name = "backup"

    def __init__(self, distance: float, speed: float, radius: float, timeout: float) -> None:
        super().__init__()
        self.distance, self.speed, self.radius, self.timeout = distance, speed, radius, timeout

    def tick(self, sense: Sense) -> tuple[float, float]:
        self.begin(sense)
        assert self._t0 is not None
        if sense.pose is None or self._start is None or sense.now - self._t0 > self.timeout:
            self.done = True
            return 0.0, 0.0
        if self._start.distance(sense.pose) >= self.distance:
            self.done = True
            return 0.0, 0.0
        if first_collision(-self.speed, 0.0, sense.obstacles, self.radius, 0.5) is not None:
            self.done = True
            return 0.0, 0.0
        return -self.speed, 0.0


class Spin(Recovery):
    name = "spin"

    def __init__(self, angle: float, speed: float, timeout: float) -> None:
        super().__init__()
        self.angle, self.speed, self.timeout = angle, speed, timeout
        self._turned = 0.0
        self._last: float | None = None

    def tick(self, sense: Sense) -> tuple[float, float]:
        self.begin(sense)
        assert self._t0 is not None
        if sense.pose is None or sense.now - self._t0 > self.timeout:
            self.done = True
            return 0.0, 0.0
        if self._last is not None:
            self._turned += abs(angle_diff(sense.pose.theta, self._last))
        self._last = sense.pose.theta
        left = abs(self.angle) - self._turned
        if left <= 0.02:
            self.done = True
            return 0.0, 0.0
        return 0.0, math.copysign(min(self.speed, max(0.2, 2.0 * left)), self.angle)


def recovery_cycle(n: int, *, wait: float, backup: float, backup_speed: float, spin: float,
                   spin_speed: float, radius: float) -> Recovery:
    """The n-th recovery (0-based) of the round robin wait → back up → spin."""
    kind = n % 3
    if kind == 0:
        return Wait(wait)
    if kind == 1:
        return BackUp(backup, backup_speed, radius, timeout=4.0 * backup / max(backup_speed, 1e-3))
    return Spin(spin, spin_speed, timeout=4.0 * abs(spin) / max(spin_speed, 1e-3) + 2.0)

