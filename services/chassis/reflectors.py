"""Reflectors: the laser's return intensities, strong where a beam ends on a retro-reflector.

The map folder's ``landmarks.yaml`` (`zenros.maps.landmarks`) places reflectors in ``map``;
a beam whose end point lies within a reflector's radius (plus a small tolerance for the
grid's half-cell walls) returns `STRONG` or more, any other finite beam a plain return
falling with range from `PLAIN_NEAR` to `PLAIN_FAR`, and a beam with no return 0. The test
runs in numpy on the ranges the ray caster returned, over the reflectors within reach only,
so a scan costs a few microseconds more.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from zenros.maps import Reflector

__all__ = ["PLAIN_FAR", "PLAIN_NEAR", "STRONG", "Reflectors"]

PLAIN_NEAR = 300.0  # a wall's return at 0 m
PLAIN_FAR = 100.0  # ... at range_max
STRONG = 1000.0  # a reflector's return at range_max; 2000 at 0 m
TOLERANCE = 0.01  # m beyond a reflector's radius still on it (walls sit on a 5 cm grid)


class Reflectors:
    """The reflectors of one map as arrays (centres and radii)."""

    def __init__(self, reflectors: Sequence[Reflector] = ()) -> None:
        self.ids = [r.id for r in reflectors]
        self.xy = np.array([(r.x, r.y) for r in reflectors], dtype=np.float64).reshape(-1, 2)
        self.radius = np.array([r.radius for r in reflectors], dtype=np.float64) + TOLERANCE

    def __len__(self) -> int:
        return len(self.ids)

    def intensities(self, x: float, y: float, theta: float, angles: np.ndarray,
                    ranges: np.ndarray, range_max: float) -> np.ndarray:
        """Float32 intensities of a scan from the laser at (x, y) facing ``theta`` in
        ``map``: ``ranges`` along the laser-frame ``angles`` (inf: no return)."""
        finite = np.isfinite(ranges)
        r = np.where(finite, ranges, 0.0).astype(np.float64)
        frac = np.clip(r / range_max, 0.0, 1.0)
        out = np.where(finite, PLAIN_NEAR - (PLAIN_NEAR - PLAIN_FAR) * frac, 0.0)
        if len(self):
            near = np.hypot(self.xy[:, 0] - x, self.xy[:, 1] - y) <= range_max + self.radius
            if near.any():
                a = angles + theta
                ex, ey = x + r * np.cos(a), y + r * np.sin(a)
                centres, radius = self.xy[near], self.radius[near]
                d2 = (ex[None, :] - centres[:, :1]) ** 2 + (ey[None, :] - centres[:, 1:]) ** 2
                on = finite & (d2 <= (radius * radius)[:, None]).any(axis=0)
                out[on] = 2 * STRONG - STRONG * frac[on]
        return out.astype(np.float32)
