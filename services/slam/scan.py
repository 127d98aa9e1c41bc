"""RangeScan: one laser scan as the mapper keeps it (ranges, beam angles, the laser on the base),
with its returns as points in the base frame and its no-return beams as clearing rays."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from zenros.se2 import Pose2

__all__ = ["RangeScan", "points_in"]


@dataclass(frozen=True)
class RangeScan:
    """A scan's ranges (float32, ``inf``/``nan`` for no return) and beam angles (radians, in
    the laser frame), from a laser at ``mount`` on the base. Returns past ``max_range`` or
    under ``range_min`` are not used; beams with no usable return clear up to ``clear_range``.
    """

    ranges: np.ndarray
    angles: np.ndarray
    mount: Pose2 = Pose2(0.0, 0.0, 0.0)
    range_min: float = 0.0
    max_range: float = 20.0
    clear_range: float = 6.0
    _cache: dict[str, np.ndarray] = field(default_factory=dict, compare=False, repr=False)

    @classmethod
    def from_laser(cls, ranges: np.ndarray | list[float], angle_min: float,
                   angle_increment: float, mount: Pose2, range_min: float, range_max: float,
                   max_laser_range: float, max_clear_range: float) -> RangeScan:
        """Build from a sensor_msgs/LaserScan's fields.

        Raises:
            ValueError: no beams, or angles/ranges that are not finite numbers.
        """
        r = np.asarray(ranges, dtype=np.float32)
        if r.ndim != 1 or len(r) == 0:
            raise ValueError(f"a scan needs at least one range, got shape {r.shape}")
        if not (math.isfinite(angle_min) and math.isfinite(angle_increment)):
            raise ValueError(f"angle_min and angle_increment must be finite, got "
                             f"{angle_min}, {angle_increment}")
        angles = angle_min + np.arange(len(r), dtype=np.float64) * angle_increment
        top = min(range_max, max_laser_range) if range_max > 0 else max_laser_range
        return cls(ranges=r, angles=angles, mount=mount, range_min=max(range_min, 0.0),
                   max_range=top, clear_range=min(max_clear_range, top))

    @property
    def valid(self) -> np.ndarray:
        """Beams with a usable return."""
        if "valid" not in self._cache:
            r = self.ranges
            with np.errstate(invalid="ignore"):
                self._cache["valid"] = (np.isfinite(r) & (r >= self.range_min)
                                        & (r <= self.max_range) & (r > 0))
        return self._cache["valid"]

    @property
    def points(self) -> np.ndarray:
        """(N, 2) float64 end points of the usable returns, in the base frame."""
        if "points" not in self._cache:
            ok = self.valid
            r = self.ranges[ok].astype(np.float64)
            a = self.angles[ok] + self.mount.theta
            self._cache["points"] = np.column_stack([self.mount.x + r * np.cos(a),
                                                     self.mount.y + r * np.sin(a)])
        return self._cache["points"]

    @property
    def clear_points(self) -> np.ndarray:
        """(M, 2) points ``clear_range`` out along the beams with no return (base frame):
        they clear the cells on the way, never mark the last one."""
        if "clear" not in self._cache:
            r = self.ranges
            with np.errstate(invalid="ignore"):
                none = ~self.valid & ~(r < self.range_min)
            a = self.angles[none] + self.mount.theta
            d = self.clear_range
            self._cache["clear"] = np.column_stack([self.mount.x + d * np.cos(a),
                                                    self.mount.y + d * np.sin(a)])
        return self._cache["clear"]


def points_in(pose: Pose2, pts: np.ndarray) -> np.ndarray:
    """``pts`` (N, 2) of the frame ``pose`` expressed in its parent."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    out = np.empty_like(pts)
    out[:, 0] = pose.x + c * pts[:, 0] - s * pts[:, 1]
    out[:, 1] = pose.y + s * pts[:, 0] + c * pts[:, 1]
    return out
