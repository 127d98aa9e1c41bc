"""Movable obstacles: circles and boxes in ``map``, with overlap tests and vectorised ray hits."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

__all__ = ["Obstacle", "ObstacleError", "ray_hits"]

Shape = Literal["circle", "box"]


class ObstacleError(ValueError):
    """An obstacle with a bad shape, size or position."""


@dataclass(frozen=True)
class Obstacle:
    """A circle (``radius``) or a box (``size_x`` by ``size_y``, turned by ``theta``)."""

    id: str
    shape: Shape
    x: float
    y: float
    theta: float = 0.0
    radius: float = 0.0
    size_x: float = 0.0
    size_y: float = 0.0

    def __post_init__(self) -> None:
        if not self.id:
            raise ObstacleError("an obstacle needs a non-empty id")
        nums = (self.x, self.y, self.theta, self.radius, self.size_x, self.size_y)
        if not all(math.isfinite(v) for v in nums):
            raise ObstacleError(f"obstacle {self.id!r}: every number must be finite")
        if self.shape == "circle":
            if self.radius <= 0:
                raise ObstacleError(f"obstacle {self.id!r}: a circle needs radius > 0")
        elif self.shape == "box":
            if self.size_x <= 0 or self.size_y <= 0:
                raise ObstacleError(f"obstacle {self.id!r}: a box needs size_x > 0 and size_y > 0")
        else:
            raise ObstacleError(f"obstacle {self.id!r}: shape must be circle or box, "
                                f"got {self.shape!r}")

    def distance(self, x: float, y: float) -> float:
        """Distance from point (x, y) to the obstacle's surface (0 inside)."""
        dx, dy = x - self.x, y - self.y
        if self.shape == "circle":
            return max(0.0, math.hypot(dx, dy) - self.radius)
        c, s = math.cos(self.theta), math.sin(self.theta)
        lx, ly = c * dx + s * dy, -s * dx + c * dy
        ex = max(abs(lx) - self.size_x / 2, 0.0)
        ey = max(abs(ly) - self.size_y / 2, 0.0)
        return math.hypot(ex, ey)

    def bounding_radius(self) -> float:
        return self.radius if self.shape == "circle" else math.hypot(self.size_x, self.size_y) / 2


def ray_hits(obstacles: list[Obstacle], ox: float, oy: float, dx: np.ndarray,
             dy: np.ndarray) -> np.ndarray:
    """Distance along each ray (origin ``ox, oy``, unit directions ``dx, dy``) to the first
    obstacle it meets; ``inf`` where it meets none. A ray starting inside one gives 0."""
    best = np.full(dx.shape, np.inf, dtype=dx.dtype)
    for ob in obstacles:
        fx, fy = ox - ob.x, oy - ob.y
        if ob.shape == "circle":
            b = fx * dx + fy * dy
            cc = fx * fx + fy * fy - ob.radius * ob.radius
            if cc <= 0:
                return np.zeros_like(best)
            disc = b * b - cc
            with np.errstate(invalid="ignore"):
                t = -b - np.sqrt(disc)
            hit = (disc >= 0) & (t >= 0)
        else:
            c, s = math.cos(ob.theta), math.sin(ob.theta)
            lx, ly = c * fx + s * fy, -s * fx + c * fy
            ldx, ldy = c * dx + s * dy, -s * dx + c * dy
            hx, hy = ob.size_x / 2, ob.size_y / 2
            if abs(lx) <= hx and abs(ly) <= hy:
                return np.zeros_like(best)
            with np.errstate(divide="ignore", invalid="ignore"):
                t1x, t2x = (-hx - lx) / ldx, (hx - lx) / ldx
                t1y, t2y = (-hy - ly) / ldy, (hy - ly) / ldy
            tnear = np.maximum(np.minimum(t1x, t2x), np.minimum(t1y, t2y))
            tfar = np.minimum(np.maximum(t1x, t2x), np.maximum(t1y, t2y))
            # a ray parallel to a slab: inside it (nan/inf bounds) or outside (no hit)
            tnear = np.where(ldx == 0, np.where(abs(lx) <= hx, np.minimum(t1y, t2y), np.inf),
                             tnear)
            tnear = np.where(ldy == 0, np.where(abs(ly) <= hy, np.minimum(t1x, t2x), np.inf),
                             tnear)
            tfar = np.where(ldx == 0, np.maximum(t1y, t2y), tfar)
            tfar = np.where(ldy == 0, np.maximum(t1x, t2x), tfar)
            hit = (tnear <= tfar) & (tnear >= 0)
            t = tnear
        np.minimum(best, np.where(hit, t, np.inf), out=best)
    return best
