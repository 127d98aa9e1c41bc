"""CostSnapshot: a copy of a costmap's master grid and its geometry (what the planner plans on)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CostSnapshot"]


@dataclass(frozen=True)
class CostSnapshot:
    """A copy of a costmap's master grid and its geometry."""

    costs: np.ndarray
    resolution: float
    origin: tuple[float, float]

    def world_to_map(self, x: float, y: float) -> tuple[int, int] | None:
        if not (math.isfinite(x) and math.isfinite(y)):
            return None
        mx = math.floor((x - self.origin[0]) / self.resolution)
        my = math.floor((y - self.origin[1]) / self.resolution)
        h, w = self.costs.shape
        return (mx, my) if 0 <= mx < w and 0 <= my < h else None
