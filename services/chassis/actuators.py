"""Actuators: the slide rail, the jacking lift and the lift's rotation as axes with travel
limits, speeds and homing (docs/robot-api.md §3.10). No Zenoh here."""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["ActuatorError", "Axis"]

HOMING, HOMED, HOMING_ERROR = 0, 1, -1  # the spec's zero_status


class ActuatorError(ValueError):
    """A move an axis refuses: past its travel, too fast, not homed."""


@dataclass
class Axis:
    """One axis between ``low`` and ``high`` (m, or rad for a rotation), moving at up to
    ``max_speed`` (``speed`` when a move asks for 0). It starts at ``position`` unhomed and
    homes by driving to ``low`` (its home switch) at ``speed``."""

    name: str
    low: float
    high: float
    speed: float
    max_speed: float
    position: float = 0.0
    zero_status: int = HOMING
    target: float | None = None
    velocity: float = 0.0
    _move_speed: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ValueError(f"{self.name}: travel [{self.low}, {self.high}] is empty")
        if not 0 < self.speed <= self.max_speed:
            raise ValueError(f"{self.name}: need 0 < speed <= max speed, got {self.speed}, "
                             f"{self.max_speed}")
        if not self.low <= self.position <= self.high:
            raise ValueError(f"{self.name}: start {self.position} outside its travel "
                             f"[{self.low}, {self.high}]")

    @property
    def ratio(self) -> float:
        """Where it stands in its travel, 0 (low) to 1 (high)."""
        return (self.position - self.low) / (self.high - self.low)

    @property
    def moving(self) -> bool:
        return self.zero_status == HOMING or self.target is not None

    def move_to(self, target: float, speed: float = 0.0) -> None:
        """Start moving to ``target`` at ``speed`` (0: the default speed).

        Raises:
            ActuatorError: not homed yet, ``target`` past the travel, ``speed`` negative,
                not finite or above the axis's maximum.
        """
        if self.zero_status != HOMED:
            raise ActuatorError(f"{self.name} is not homed yet (zero_status "
                                f"{self.zero_status})")
        if not math.isfinite(target) or not self.low <= target <= self.high:
            raise ActuatorError(f"{self.name}: {target:g} is past its travel "
                                f"[{self.low:g}, {self.high:g}]")
        if not math.isfinite(speed) or speed < 0 or speed > self.max_speed:
            raise ActuatorError(f"{self.name}: speed {speed:g} must be 0 (default) up to "
                                f"{self.max_speed:g}")
        self.target = target
        self._move_speed = speed or self.speed

    def stop(self) -> None:
        """Stop where it is."""
        self.target = None
        self.velocity = 0.0

    def step(self, dt: float) -> bool:
        """Advance ``dt`` seconds; True when a move or the homing ended in this step."""
        if self.zero_status == HOMING:
            goal, speed = self.low, self.speed
        elif self.target is not None:
            goal, speed = self.target, self._move_speed
        else:
            return False
        gap = goal - self.position
        reach = speed * dt
        if abs(gap) <= reach:
            self.position = goal
            self.velocity = 0.0
            if self.zero_status == HOMING:
                self.zero_status = HOMED
            self.target = None
            return True
        self.position += math.copysign(reach, gap)
        self.velocity = math.copysign(speed, gap)
        return False
