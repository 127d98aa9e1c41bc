"""Battery: state of charge that drains with time and motion and charges while docked."""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Battery", "BatteryConfig"]


@dataclass(frozen=True)
class BatteryConfig:
    """A pack of ``capacity`` Ah at ``voltage`` V. The base draws ``idle_current`` A always,
    plus ``motion_current`` A per m/s and ``turn_current`` A per rad/s; the dock charges
    at ``charge_current`` A."""

    capacity: float = 20.0
    voltage: float = 24.0
    idle_current: float = 2.0
    motion_current: float = 6.0
    turn_current: float = 2.0
    charge_current: float = 10.0
    initial: float = 0.9

    def __post_init__(self) -> None:
        for name in ("capacity", "voltage", "idle_current", "motion_current", "turn_current",
                     "charge_current"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"battery {name} must be a finite number >= 0, got {v}")
        if self.capacity <= 0:
            raise ValueError("battery capacity must be > 0")
        if not 0 <= self.initial <= 1:
            raise ValueError(f"battery initial charge must be within 0..1, got {self.initial}")


class Battery:
    """Charge in Ah; ``current`` is positive while charging, negative while draining."""

    def __init__(self, config: BatteryConfig) -> None:
        self.config = config
        self.charge = config.capacity * config.initial
        self.current = 0.0
        self.charging = False

    @property
    def percentage(self) -> float:
        return self.charge / self.config.capacity

    @property
    def full(self) -> bool:
        return self.percentage >= 0.999

    @property
    def empty(self) -> bool:
        return self.charge <= 0.0

    @property
    def voltage(self) -> float:
        """A simple discharge curve: 90 % of nominal when empty, 105 % when full."""
        return self.config.voltage * (0.9 + 0.15 * self.percentage)

    def update(self, dt: float, linear: float, angular: float, docked: bool) -> None:
        """Drain for ``dt`` seconds at the given speeds; charge instead while docked."""
        c = self.config
        draw = c.idle_current + c.motion_current * abs(linear) + c.turn_current * abs(angular)
        self.charging = docked and not self.full and c.charge_current > 0
        self.current = (c.charge_current if self.charging else 0.0) - draw
        if docked and self.current < 0 and self.full:
            self.current = 0.0  # the dock supplies the base once the pack is full
        self.charge = min(max(self.charge + self.current * dt / 3600.0, 0.0), c.capacity)
