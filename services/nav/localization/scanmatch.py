"""ScanMatcher: corrects the odometry pose against the map with each laser scan.

A likelihood field (a Gaussian of the distance to the nearest occupied map cell, from a
Euclidean distance transform) scores a scan placed at a candidate pose: the mean field
value under its end points. `match` searches a window round the predicted pose, coarse
then fine (x, y and heading), and returns the best pose and its score; points that hit
nothing in the map (people, boxes) just score 0. This is the correlative matcher of
Karto/Cartographer's first stage, without the branch-and-bound, since the window is small.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from zenros.maps import GridMap
from zenros.se2 import Pose2, wrap_angle

__all__ = ["MatchParams", "ScanMatcher"]


@dataclass(frozen=True)
class MatchParams:
    sigma: float = 0.05
    """Metres: how fast a point's score falls off with its distance to a map obstacle."""
    window_xy: float = 0.15
    window_theta: float = 0.06
    wide_xy: float = 0.5
    wide_theta: float = 0.35
    """The window of a relocalisation (`match` with ``wide``): a pose given by hand or kept
    from an earlier session, which may be off by more than tracking's window (Karto's
    correlation window is ±0.25 m, ±0.349 rad)."""
    coarse_xy: float = 0.05
    coarse_theta: float = 0.02
    fine_xy: float = 0.0125
    fine_theta: float = 0.005
    max_points: int = 120
    min_score: float = 0.25
    """Mean point score below which a match is not trusted (the scan does not fit)."""


class ScanMatcher:
    """Scores and matches scans against one map."""

    def __init__(self, grid: GridMap, params: MatchParams = MatchParams()) -> None:
        self.p = params
        self.res = grid.resolution
        self.ox, self.oy = grid.origin[0], grid.origin[1]
        occupied = grid.grid >= 65
        dist = ndimage.distance_transform_edt(~occupied) * self.res
        field = np.exp(-(dist ** 2) / (2 * params.sigma ** 2)).astype(np.float32)
        # a border of zeros: points off the map land there after clipping
        self.field = np.pad(field, 1)
        self.h, self.w = self.field.shape
        self.flat = self.field.ravel()
        self.ox -= self.res
        self.oy -= self.res

    def _scores(self, pts: np.ndarray, poses: np.ndarray) -> np.ndarray:
        """Mean field value of ``pts`` (N, 2, robot frame) at each of ``poses`` (K, 3)."""
        inv = np.float32(1.0 / self.res)
        c = np.cos(poses[:, 2]).astype(np.float32)[:, None]
        s = np.sin(poses[:, 2]).astype(np.float32)[:, None]
        px = pts[:, 0].astype(np.float32)[None, :] * inv
        py = pts[:, 1].astype(np.float32)[None, :] * inv
        u = ((poses[:, 0:1] - self.ox) * inv).astype(np.float32) + (c * px - s * py)
        v = ((poses[:, 1:2] - self.oy) * inv).astype(np.float32) + (s * px + c * py)
        mx = np.clip(u, 0, self.w - 1).astype(np.int32)
        my = np.clip(v, 0, self.h - 1).astype(np.int32)
        my *= self.w
        my += mx
        out: np.ndarray = self.flat[my].mean(axis=1)
        return out

    def score(self, pts: np.ndarray, pose: Pose2) -> float:
        return float(self._scores(self._thin(pts), np.array([pose]))[0])

    def _thin(self, pts: np.ndarray) -> np.ndarray:
        if len(pts) > self.p.max_points:
            pts = pts[np.linspace(0, len(pts) - 1, self.p.max_points).astype(int)]
        return pts

    @staticmethod
    def _grid(center: Pose2, wxy: float, sxy: float, wth: float, sth: float) -> np.ndarray:
        d = np.arange(-wxy, wxy + 1e-9, sxy)
        t = np.arange(-wth, wth + 1e-9, sth)
        gx, gy, gt = np.meshgrid(center.x + d, center.y + d, center.theta + t, indexing="ij")
        return np.column_stack([gx.ravel(), gy.ravel(), gt.ravel()])

    def match(self, pts: np.ndarray, guess: Pose2, wide: bool = False) -> tuple[Pose2, float]:
        """The best pose within the window round ``guess`` (the wide one with ``wide``) for
        scan points ``pts`` (in the robot frame), and its score (0..1). Returns ``guess`` if
        there are no points."""
        pts = self._thin(pts)
        if len(pts) < 10:
            return guess, 0.0
        p = self.p
        wxy, wth = (p.wide_xy, p.wide_theta) if wide else (p.window_xy, p.window_theta)
        coarse = self._grid(guess, wxy, p.coarse_xy, wth, p.coarse_theta)
        sc = self._scores(pts, coarse)
        best = coarse[int(np.argmax(sc))]
        fine = self._grid(Pose2(*best), p.coarse_xy / 2, p.fine_xy, p.coarse_theta / 2,
                          p.fine_theta)
        sf = self._scores(pts, fine)
        k = int(np.argmax(sf))
        x, y, th = fine[k]
        return Pose2(float(x), float(y), wrap_angle(float(th))), float(sf[k])
