"""Reflector detection: a scan's strong returns, clustered into reflector centres.

A beam is strong when its intensity is at least ``min_intensity`` (the simulated laser
returns 1000-2000 on a reflector, 100-300 elsewhere; docs/chassis.md). Strong end points in
beam order join one cluster while each is within ``max_gap`` of the last (a full-circle
scan's first and last clusters join across the seam); a cluster wider than ``max_width`` is
not a reflector (a mirror, a glass door) and is dropped. A reflector's centre is the mean
of its points, in ``base_link`` (the laser's ``mount`` applied).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from zenros.se2 import Pose2

__all__ = ["DetectParams", "Detections", "detect"]


@dataclass(frozen=True)
class DetectParams:
    min_intensity: float = 1000.0
    max_gap: float = 0.15
    """Metres between consecutive strong points of one reflector."""
    max_width: float = 0.3
    """Metres: a cluster wider than this is not a reflector."""


@dataclass(frozen=True)
class Detections:
    """Reflector centres (``xy``, shape (n, 2), in ``base_link``) and the strong returns
    each was seen with (``returns``)."""

    xy: np.ndarray
    returns: np.ndarray

    def __len__(self) -> int:
        return len(self.xy)


def _clusters(pts: np.ndarray, max_gap: float, closed: bool) -> list[np.ndarray]:
    """Index runs of ``pts`` (in beam order) whose neighbours are within ``max_gap``."""
    if len(pts) == 0:
        return []
    gaps = np.hypot(*(pts[1:] - pts[:-1]).T) > max_gap
    cuts = np.nonzero(gaps)[0] + 1
    runs = np.split(np.arange(len(pts)), cuts)
    if closed and len(runs) > 1 and math.dist(pts[-1], pts[0]) <= max_gap:
        runs[0] = np.concatenate([runs[-1], runs[0]])
        runs.pop()
    return runs


def detect(ranges: np.ndarray, intensities: np.ndarray, angle_min: float,
           angle_increment: float, range_min: float, range_max: float,
           mount: Pose2 | None = None, params: DetectParams | None = None) -> Detections:
    """The reflectors in one scan (none when it has no intensities).

    Raises:
        ValueError: intensities and ranges differ in length, or the angles are not finite.
    """
    mount = mount or Pose2()
    params = params or DetectParams()
    ranges = np.asarray(ranges, dtype=np.float64)
    intensities = np.asarray(intensities, dtype=np.float64)
    empty = Detections(np.zeros((0, 2)), np.zeros(0, dtype=np.int64))
    if intensities.size == 0:
        return empty
    if intensities.shape != ranges.shape:
        raise ValueError(f"the scan has {ranges.size} ranges but {intensities.size} "
                         "intensities")
    if not (math.isfinite(angle_min) and math.isfinite(angle_increment)):
        raise ValueError(f"the scan's angles are not finite (angle_min {angle_min}, "
                         f"angle_increment {angle_increment})")
    n = ranges.size
    ok = np.isfinite(ranges) & (ranges >= range_min) & (ranges <= range_max) \
        & (intensities >= params.min_intensity)
    idx = np.nonzero(ok)[0]
    if idx.size == 0:
        return empty
    a = angle_min + angle_increment * idx + mount.theta
    pts = np.column_stack([mount.x + ranges[idx] * np.cos(a),
                           mount.y + ranges[idx] * np.sin(a)])
    closed = abs(angle_increment * n - 2 * math.pi) < 1e-6
    centres, returns = [], []
    for run in _clusters(pts, params.max_gap, closed):
        p = pts[run]
        if len(p) > 1 and math.dist(p.min(axis=0), p.max(axis=0)) > params.max_width:
            continue
        centres.append(p.mean(axis=0))
        returns.append(len(p))
    if not centres:
        return empty
    return Detections(np.array(centres), np.array(returns, dtype=np.int64))
