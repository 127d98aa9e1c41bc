"""The estimators behind the robot's calibrations: what the sensors measured in, what is
wrong with them out. No simulator here: the same code would calibrate a real robot.

- `gyro_bias`: a still robot's gyro reads its bias (plus noise): the mean, and how well the
  samples agree.
- `match_scans`: point-to-line ICP of one laser scan onto another.
- `laser_mount`: the laser's pose on the base from pairs of scans and the odometry between
  them (the hand-eye problem in the plane): the laser moves by ``M⁻¹ B M`` when the base
  moves by ``B``. Turning in place fixes the base's origin in the laser's frame; driving
  straight fixes the yaw.
- `board_edges`, `image_edges`, `camera_lens`: a board standing in front of the robot, its
  edges found by the laser (range steps) and in the camera's middle row (its colour); the
  focal length and yaw of the camera that best map the one onto the other
  (u = cx - f tan(bearing - yaw)).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.spatial import cKDTree
from zenros.se2 import Pose2, wrap_angle

__all__ = [
    "LensEstimate",
    "MountEstimate",
    "ScanPair",
    "board_edges",
    "camera_lens",
    "gyro_bias",
    "image_edges",
    "laser_mount",
    "match_scans",
    "normals",
    "scan_points",
]


def gyro_bias(samples: Sequence[float]) -> tuple[float, float]:
    """The bias of a gyro that stood still for ``samples`` (rad/s), and the standard error of
    that mean."""
    if len(samples) < 2:
        raise ValueError("a gyro bias needs at least two samples")
    a = np.asarray(samples, dtype=np.float64)
    return float(a.mean()), float(a.std(ddof=1) / math.sqrt(a.size))


def scan_points(ranges: np.ndarray, angle_min: float, angle_increment: float,
                range_max: float) -> np.ndarray:
    """The (n, 2) points of a scan's finite returns, in the laser's frame."""
    r = np.asarray(ranges, dtype=np.float64)
    a = angle_min + angle_increment * np.arange(r.size)
    ok = np.isfinite(r) & (r < range_max)
    return np.column_stack((r[ok] * np.cos(a[ok]), r[ok] * np.sin(a[ok])))


def _rot(theta: float) -> np.ndarray:
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def normals(points: np.ndarray, tree: cKDTree, k: int = 6) -> np.ndarray:
    """Each point's unit normal: the least-spread direction of its ``k`` nearest points."""
    _, idx = tree.query(points, k=min(k, len(points)))
    near = points[idx] - points[idx].mean(axis=1, keepdims=True)
    cov = np.einsum("nki,nkj->nij", near, near)
    _, vecs = np.linalg.eigh(cov)  # ascending eigenvalues: column 0 spreads least
    normals: np.ndarray = vecs[:, :, 0]
    return normals


def match_scans(ref: np.ndarray, scan: np.ndarray, guess: Pose2, *, iterations: int = 30,
                max_pair: float = 0.3) -> tuple[Pose2, float]:
    """Where ``scan``'s frame is in ``ref``'s, by point-to-line ICP (Chen and Medioni; the
    line is each reference point's local wall, so a sparse scan's spacing biases nothing)
    from ``guess``, and the RMS distance (m) of the matched points to their lines; points
    further than ``max_pair`` from their match are left out."""
    if len(ref) < 10 or len(scan) < 10:
        raise ValueError("a scan match needs at least ten points in each scan")
    tree = cKDTree(ref)
    lines = normals(ref, tree)
    pose = guess
    rms = math.inf
    for _ in range(iterations):
        moved = scan @ _rot(pose.theta).T + (pose.x, pose.y)
        dist, idx = tree.query(moved, distance_upper_bound=max_pair)
        keep = np.isfinite(dist)
        if keep.sum() < 10:
            raise ValueError("the scans do not overlap")
        p, q, n = moved[keep], ref[idx[keep]], lines[idx[keep]]
        r = np.einsum("ij,ij->i", n, p - q)  # each point's distance to its line
        jac = np.column_stack((n[:, 1] * p[:, 0] - n[:, 0] * p[:, 1], n[:, 0], n[:, 1]))
        step, *_ = np.linalg.lstsq(jac, -r, rcond=None)
        dtheta, tx, ty = (float(v) for v in step)
        pose = Pose2(tx, ty, dtheta) * pose
        rms = float(np.sqrt(np.mean(r ** 2)))
        if abs(dtheta) < 1e-7 and math.hypot(tx, ty) < 1e-6:
            break
    return pose, rms


@dataclass(frozen=True)
class ScanPair:
    """The base's motion between two scans as the odometry saw it (``base``) and the laser's
    as the scans matched it (``laser``)."""

    base: Pose2
    laser: Pose2


@dataclass(frozen=True)
class MountEstimate:
    """The laser's pose on the base and the RMS residual (m) of the pairs' translations."""

    mount: Pose2
    residual: float


def _fit_offset(pairs: Sequence[ScanPair], yaw: float) -> tuple[np.ndarray, float]:
    """For a mount yaw: the least-squares mount position and the sum of squared residuals.
    Each pair says R(yaw) t_laser = (R(Δ) - I) l + t_base, linear in l."""
    rows, rhs = [], []
    r = _rot(yaw)
    for p in pairs:
        rows.append(_rot(p.base.theta) - np.eye(2))
        rhs.append(r @ (p.laser.x, p.laser.y) - (p.base.x, p.base.y))
    a, b = np.vstack(rows), np.concatenate(rhs)
    offset, *_ = np.linalg.lstsq(a, b, rcond=None)
    return offset, float(np.sum((a @ offset - b) ** 2))


def laser_mount(pairs: Sequence[ScanPair]) -> MountEstimate:
    """The laser's pose on the base that best explains ``pairs``: yaw by a bounded search
    (from a coarse grid), the position by linear least squares for each yaw."""
    turning = sum(1 for p in pairs if abs(p.base.theta) > 0.1)
    driving = sum(1 for p in pairs if math.hypot(p.base.x, p.base.y) > 0.05
                  and abs(p.base.theta) < 0.05)
    if turning < 2 or driving < 1:
        raise ValueError(f"a laser mount needs at least two turns and one straight move "
                         f"between scans; got {turning} and {driving}")
    grid = np.linspace(-math.pi, math.pi, 73)
    costs = [_fit_offset(pairs, float(y))[1] for y in grid]
    best = float(grid[int(np.argmin(costs))])
    step = grid[1] - grid[0]
    found = minimize_scalar(lambda y: _fit_offset(pairs, y)[1], method="bounded",
                            bounds=(best - step, best + step), options={"xatol": 1e-6})
    yaw = wrap_angle(float(found.x))
    offset, cost = _fit_offset(pairs, yaw)
    return MountEstimate(Pose2(float(offset[0]), float(offset[1]), yaw),
                         math.sqrt(cost / (2 * len(pairs))))


def board_edges(ranges: np.ndarray, angle_min: float, angle_increment: float,
                window: tuple[float, float], *, step: float = 0.3, width: tuple[float, float]
                = (0.2, 1.5)) -> tuple[tuple[float, float], tuple[float, float]] | None:
    """The nearest board the laser sees within the bearings ``window`` (laser frame): a run
    of returns standing ``step`` m or more in front of the returns either side, ``width``
    metres wide. Its two edges as (bearing, range), the lower bearing first; each edge's
    bearing halfway between the board's last beam and the background's first (so a beam's
    spacing biases neither edge)."""
    r = np.asarray(ranges, dtype=np.float64)
    a = angle_min + angle_increment * np.arange(r.size)
    r = np.where(np.isfinite(r), r, 1e6)  # no return: far behind anything
    best: tuple[float, tuple[tuple[float, float], tuple[float, float]]] | None = None
    i = 1
    while i < r.size - 1:
        if not (window[0] <= a[i] <= window[1]) or not r[i - 1] - r[i] >= step:
            i += 1
            continue
        j = i
        while j + 1 < r.size and abs(r[j + 1] - r[j]) < step / 2:
            j += 1
        if j + 1 < r.size and r[j + 1] - r[j] >= step and a[j] <= window[1]:
            lo, hi = (a[i - 1] + a[i]) / 2, (a[j] + a[j + 1]) / 2
            span = math.hypot(r[j] * math.cos(a[j]) - r[i] * math.cos(a[i]),
                              r[j] * math.sin(a[j]) - r[i] * math.sin(a[i]))
            near = float(r[i:j + 1].mean())
            if width[0] <= span <= width[1] and (best is None or near < best[0]):
                best = (near, ((float(lo), float(r[i])), (float(hi), float(r[j]))))
        i = j + 1
    return None if best is None else best[1]


def image_edges(row: np.ndarray, colour: tuple[int, int, int], *, tolerance: float = 0.25
                ) -> tuple[float, float] | None:
    """The widest run of ``colour`` (any shade of it: the pixels' chromaticity within
    ``tolerance``) in an image row: its left and right boundaries as column coordinates
    (the left one's pixel starts there, the right one's pixel ends there)."""
    px = np.asarray(row, dtype=np.float64)
    sums = px.sum(axis=1, keepdims=True)
    want = np.asarray(colour, dtype=np.float64) / sum(colour)
    match = (sums[:, 0] > 30) & (np.abs(px / np.maximum(sums, 1) - want).max(axis=1)
                                 < tolerance * want.max())
    best: tuple[int, int] | None = None
    start = -1
    for k, m in enumerate([*match.tolist(), False]):
        if m and start < 0:
            start = k
        elif not m and start >= 0:
            if best is None or k - start > best[1] - best[0]:
                best = (start, k)
            start = -1
    return None if best is None else (float(best[0]), float(best[1]))


@dataclass(frozen=True)
class LensEstimate:
    """A camera's focal length (pixels), its yaw on the base (rad), and the RMS residual
    (pixels)."""

    f: float
    yaw: float
    residual: float


def _fit_lens(obs: np.ndarray, cx: float, yaw: float) -> tuple[float, float]:
    """For a yaw: the least-squares focal length and the sum of squared residuals."""
    t = -np.tan(obs[:, 0] - yaw)
    d = obs[:, 1] - cx
    f = float(t @ d / (t @ t))
    return f, float(np.sum((f * t - d) ** 2))


def camera_lens(observations: Sequence[tuple[float, float]], cx: float,
                yaw_bound: float = 0.4) -> LensEstimate:
    """The focal length and yaw that best explain ``observations``: (bearing from the camera
    in the base frame, column where the camera saw it), with the principal point at column
    ``cx`` (a turn of the camera and a shift of its principal point look alike to first
    order, so one is taken as known: the image's centre, as a rectified image has it). For a
    yaw, f is linear least squares; the yaw is a bounded search within ±``yaw_bound``."""
    obs = np.asarray(observations, dtype=np.float64).reshape(-1, 2)
    if len(obs) < 6 or float(np.ptp(obs[:, 0])) < 0.2:
        raise ValueError(f"a camera calibration needs six or more sightings over 0.2 rad of "
                         f"bearings; got {len(obs)}")
    grid = np.linspace(-yaw_bound, yaw_bound, 41)
    costs = [_fit_lens(obs, cx, float(y))[1] for y in grid]
    best = float(grid[int(np.argmin(costs))])
    step = float(grid[1] - grid[0])
    found = minimize_scalar(lambda y: _fit_lens(obs, cx, y)[1], method="bounded",
                            bounds=(best - step, best + step), options={"xatol": 1e-7})
    f, cost = _fit_lens(obs, cx, float(found.x))
    return LensEstimate(f, float(found.x), math.sqrt(cost / len(obs)))
