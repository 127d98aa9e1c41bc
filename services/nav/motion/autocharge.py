"""AutoCharge: decides when a low battery should send the idle robot to its dock."""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["AutoCharge"]


@dataclass
class AutoCharge:
    """``due`` is true when enabled, the battery is below ``threshold`` (0..1), the robot
    is neither charging nor docked nor busy, and no attempt was made in ``retry_period``."""

    enabled: bool = False
    threshold: float = 0.2
    retry_period: float = 60.0
    _last: float = -math.inf

    def due(self, battery: float | None, charging: bool, docked: bool, busy: bool,
            now: float) -> bool:
        if not self.enabled or battery is None or charging or docked or busy:
            return False
        if battery >= self.threshold or now - self._last < self.retry_period:
            return False
        self._last = now
        return True
