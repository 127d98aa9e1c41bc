"""Actuators: the slide rail, the jacking lift and the lift's rotation as axes with travel
limits, speeds and homing (docs/robot-api.md §3.10). No Zenoh here.

An axis moves in the spec's modes (§9.2 ``slide_action``): homing (to its low end, its home
switch), speed mode (a signed speed for a time), stop, and position mode (to a target within
its travel). A speed move that reaches an end of the travel stops there with a fault (the
limit switch), which the next command clears."""

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
    fault: str = ""
    _move_speed: float = 0.0
    _run_left: float = 0.0  # speed mode: seconds still to run

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
        return self.zero_status == HOMING or self.target is not None or self._run_left > 0

    def move_to(self, target: float, speed: float = 0.0) -> None:
        """Start moving to ``target`` at ``speed`` (0: the default speed).

        Raises:
            ActuatorError: not homed yet, ``target`` past the travel, ``speed`` negative,
                not finite or above the axis's maximum.
        """
        self._check_homed()
        if not math.isfinite(target) or not self.low <= target <= self.high:
            raise ActuatorError(f"{self.name}: {target:g} is past its travel "
                                f"[{self.low:g}, {self.high:g}]")
        if not math.isfinite(speed) or speed < 0 or speed > self.max_speed:
            raise ActuatorError(f"{self.name}: speed {speed:g} must be 0 (default) up to "
                                f"{self.max_speed:g}")
        self.stop()
        self.target = target
        self._move_speed = speed or self.speed

    def run(self, speed: float, duration: float) -> None:
        """Speed mode: move at ``speed`` (signed: + towards the high end; 0: the default
        speed, + ) for ``duration`` seconds. Reaching an end of the travel first stops it
        there with a `fault`.

        Raises:
            ActuatorError: not homed yet, ``speed`` above the maximum or not finite,
                ``duration`` not positive, or already at the end it would run into.
        """
        self._check_homed()
        if not math.isfinite(speed) or abs(speed) > self.max_speed:
            raise ActuatorError(f"{self.name}: speed {speed:g} must be within "
                                f"±{self.max_speed:g} (0: the default)")
        if not math.isfinite(duration) or duration <= 0:
            raise ActuatorError(f"{self.name}: a speed move needs a time > 0 s, got "
                                f"{duration:g}")
        speed = speed or self.speed
        end = self.high if speed > 0 else self.low
        if self.position == end:
            raise ActuatorError(f"{self.name} is at its {self._end_name(end)} limit "
                                f"({end:g}): it cannot move further that way")
        self.stop()
        self._move_speed = speed
        self._run_left = duration

    def home(self) -> None:
        """Homing: back to the home switch at the low end, at the default speed; moves are
        refused until it is there."""
        self.stop()
        self.zero_status = HOMING

    def stop(self) -> None:
        """Stop where it is (and clear a fault); a homing stopped short is a homing error
        (zero_status -1): moves are refused until it homes again."""
        self.target = None
        self.velocity = 0.0
        self._run_left = 0.0
        self.fault = ""
        if self.zero_status == HOMING:
            self.zero_status = HOMING_ERROR
            self.fault = f"{self.name}: homing stopped before the home switch"

    def _check_homed(self) -> None:
        if self.zero_status != HOMED:
            raise ActuatorError(f"{self.name} is not homed yet (zero_status "
                                f"{self.zero_status})")

    def _end_name(self, end: float) -> str:
        return "high" if end == self.high else "low"

    def step(self, dt: float) -> bool:
        """Advance ``dt`` seconds; True when a move or the homing ended in this step."""
        if self._run_left > 0:
            return self._run_step(dt)
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

    def _run_step(self, dt: float) -> bool:
        t = min(dt, self._run_left)
        speed = self._move_speed
        end = self.high if speed > 0 else self.low
        gap = abs(end - self.position)
        if gap <= abs(speed) * t:  # the limit switch
            left = self._run_left - gap / abs(speed)
            self.stop()
            self.position = end
            self.fault = (f"{self.name} reached its {self._end_name(end)} limit ({end:g}) "
                          f"with {left:.2f} s of its run left")
            return True
        self.position += speed * t
        self._run_left -= t
        self.velocity = speed
        if self._run_left <= 1e-9:
            self._run_left = 0.0
            self.velocity = 0.0
            return True
        return False
