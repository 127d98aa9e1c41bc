"""Correlative scan matching (Olson 2009; Karto's sequential and loop matcher).

A `CorrelationGrid` rasterises reference points (earlier scans placed at their poses) and
smears each with a Gaussian of the smear deviation, so a cell holds how likely a return is
there (0..1). `match` scores candidate poses in a window round a guess, the response being
the mean grid value under the scan's points, coarse then fine, and estimates the match's
covariance from the spread of the coarse responses near the best one (Karto: cells within
0.1 of the best). A wide window (loop closure) first searches a max-pooled copy of the grid,
whose values bound the fine ones, and refines only the best few coarse cells.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from zenros.se2 import Pose2, wrap_angle

__all__ = ["CorrelationGrid", "MatchResult", "Window", "match"]


class CorrelationGrid:
    """Reference points rasterised at ``resolution`` and smeared by ``sigma`` (metres).

    ``margin`` metres of border round the points' bounding box (the search window and the
    scan's reach beyond the reference should fit in it; points off the grid score 0).
    """

    def __init__(self, points: np.ndarray, resolution: float, sigma: float,
                 margin: float, bounds: tuple[float, float, float, float] | None = None
                 ) -> None:
        self.res = resolution
        if bounds is None:
            if len(points):
                lo = points.min(axis=0)
                hi = points.max(axis=0)
            else:
                lo = hi = np.zeros(2)
            bounds = (lo[0], lo[1], hi[0], hi[1])
        x0, y0, x1, y1 = bounds
        self.ox = math.floor((x0 - margin) / resolution) * resolution
        self.oy = math.floor((y0 - margin) / resolution) * resolution
        self.w = int(math.ceil((x1 + margin - self.ox) / resolution)) + 1
        self.h = int(math.ceil((y1 + margin - self.oy) / resolution)) + 1
        # each cell holds exp(-d²/2σ²), d the distance from its centre to the nearest
        # reference point (within the kernel's reach): Olson's rasterised likelihood,
        # a maximum, never a sum, so dense walls keep a sharp peak at their place
        field = np.zeros(self.h * self.w, dtype=np.float32)
        if len(points):
            reach = max(1, math.ceil(2.0 * sigma / resolution))
            u = (points[:, 0] - self.ox) / resolution
            v = (points[:, 1] - self.oy) / resolution
            iu, iv = np.floor(u).astype(np.int64), np.floor(v).astype(np.int64)
            ok = ((iu >= reach) & (iu < self.w - reach) & (iv >= reach)
                  & (iv < self.h - reach))
            u, v, iu, iv = u[ok], v[ok], iu[ok], iv[ok]
            # one point per cell, at the mean of the points in it: many scans of a wall
            # average their range noise, and the stamping costs what the cells do
            cells, inverse, count = np.unique(iv * self.w + iu, return_inverse=True,
                                              return_counts=True)
            u = np.bincount(inverse, u) / count
            v = np.bincount(inverse, v) / count
            iu, iv = cells % self.w, cells // self.w
            k = np.arange(-reach, reach + 1)
            ku, kv = np.meshgrid(k, k)
            ku, kv = ku.ravel(), kv.ravel()
            cu = iu[:, None] + ku[None, :]
            cv = iv[:, None] + kv[None, :]
            d2 = ((cu + 0.5 - u[:, None]) ** 2 + (cv + 0.5 - v[:, None]) ** 2)
            val = np.exp(-d2 * (resolution * resolution / (2.0 * sigma * sigma)))
            np.maximum.at(field, (cv * self.w + cu).ravel(), val.astype(np.float32).ravel())
        self.field = field.reshape(self.h, self.w)
        self.field[0, :] = self.field[-1, :] = 0.0
        self.field[:, 0] = self.field[:, -1] = 0.0

    def pooled(self, factor: int) -> CorrelationGrid:
        """A copy whose cell holds the maximum of the ``factor`` x ``factor`` block of cells
        at and above-right of it: its score of a pose bounds the fine score of every pose
        within ``factor`` cells up/right of it (Cartographer's precomputation grids)."""
        out = object.__new__(CorrelationGrid)
        out.res, out.ox, out.oy, out.w, out.h = self.res, self.ox, self.oy, self.w, self.h
        f = ndimage.maximum_filter(self.field, size=factor, mode="constant",
                                   origin=-(factor // 2))
        f[0, :] = f[-1, :] = 0.0
        f[:, 0] = f[:, -1] = 0.0
        out.field = f
        return out

    def scores(self, pts: np.ndarray, poses: np.ndarray) -> np.ndarray:
        """Mean field value under ``pts`` (N, 2, base frame) at each of ``poses`` (K, 3)."""
        thetas, inverse = np.unique(poses[:, 2], return_inverse=True)
        inv = 1.0 / self.res
        c = np.cos(thetas)[:, None]
        s = np.sin(thetas)[:, None]
        px, py = pts[None, :, 0].astype(np.float32), pts[None, :, 1].astype(np.float32)
        rx = ((c * px - s * py) * inv).astype(np.float32)  # (T, N)
        ry = ((s * px + c * py) * inv).astype(np.float32)
        u = ((poses[:, 0:1] - self.ox) * inv).astype(np.float32) + rx[inverse]
        v = ((poses[:, 1:2] - self.oy) * inv).astype(np.float32) + ry[inverse]
        iu = u.astype(np.int32)
        iv = v.astype(np.int32)
        np.minimum(np.maximum(iu, 0, out=iu), self.w - 1, out=iu)
        np.minimum(np.maximum(iv, 0, out=iv), self.h - 1, out=iv)
        iv *= self.w
        iv += iu
        out: np.ndarray = self.field.ravel()[iv].mean(axis=1)
        return out

    def bilinear(self, pts: np.ndarray, pose: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """At one ``pose``: per point of ``pts``, the interpolated field and its gradient (per
        metre) in x and y: (f, df/dx, df/dy), each (N,); ``f.mean()`` is the score."""
        c, s = math.cos(pose[2]), math.sin(pose[2])
        inv = 1.0 / self.res
        u = (pose[0] + c * pts[:, 0] - s * pts[:, 1] - self.ox) * inv - 0.5
        v = (pose[1] + s * pts[:, 0] + c * pts[:, 1] - self.oy) * inv - 0.5
        iu = np.clip(np.floor(u).astype(np.int64), 0, self.w - 2)
        iv = np.clip(np.floor(v).astype(np.int64), 0, self.h - 2)
        fu, fv = np.clip(u - iu, 0, 1), np.clip(v - iv, 0, 1)
        f = self.field
        f00, f10 = f[iv, iu], f[iv, iu + 1]
        f01, f11 = f[iv + 1, iu], f[iv + 1, iu + 1]
        val = (1 - fu) * (1 - fv) * f00 + fu * (1 - fv) * f10 + (1 - fu) * fv * f01 + fu * fv * f11
        du = ((1 - fv) * (f10 - f00) + fv * (f11 - f01)) * inv
        dv = ((1 - fu) * (f01 - f00) + fu * (f11 - f10)) * inv
        return val, du, dv

    def lattice_scores(self, pts: np.ndarray, center: np.ndarray, cells: int, stride: int,
                       thetas: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Scores of ``pts`` on a lattice of whole-cell shifts: (x, y) = ``center`` +
        k·``stride`` cells for k in [-cells, cells] each way, at each heading of ``thetas``.

        Returns (poses (K, 3), scores (K,)). Cheap: each heading rotates the points once and
        every shift is one integer add per point. Points whose shifts could leave the grid
        score 0 at that heading.
        """
        inv = 1.0 / self.res
        k = np.arange(-cells, cells + 1) * stride
        shift = (k[:, None] * self.w + k[None, :]).ravel().astype(np.int64)  # (dy, dx) flat
        reach = cells * stride
        c, s = np.cos(thetas)[:, None], np.sin(thetas)[:, None]
        wx = center[0] + c * pts[None, :, 0] - s * pts[None, :, 1]
        wy = center[1] + s * pts[None, :, 0] + c * pts[None, :, 1]
        iu = np.floor((wx - self.ox) * inv).astype(np.int64)
        iv = np.floor((wy - self.oy) * inv).astype(np.int64)
        ok = (iu >= reach) & (iu < self.w - reach) & (iv >= reach) & (iv < self.h - reach)
        base = np.where(ok, iv * self.w + iu, 0)  # (T, N); 0 shifts stay valid indices
        flat = self.field.ravel()
        n = max(1, pts.shape[0])
        out = np.empty((len(thetas), len(shift)), dtype=np.float32)
        for t in range(len(thetas)):
            vals = flat[base[t][None, :] + shift[:, None]]  # (S, N)
            vals *= ok[t][None, :]
            out[t] = vals.sum(axis=1) / n
        # poses: heading-major, then dy, then dx
        dy, dx = np.meshgrid(k, k, indexing="ij")
        xy = np.column_stack([center[0] + dx.ravel() * self.res, center[1] + dy.ravel() * self.res])
        poses = np.column_stack([np.tile(xy, (len(thetas), 1)), np.repeat(thetas, len(shift))])
        return poses, out.ravel()


@dataclass(frozen=True)
class Window:
    """A search window: ±``xy`` metres in steps of ``xy_step``, ±``theta`` radians in steps of
    ``theta_step``; ``fine_xy``/``fine_theta`` the refinement steps round the best cell.
    ``pool`` > 1 searches the coarse level on a max-pooled grid (wide windows);
    ``penalty``: Karto's distance and angle variance penalties (sequential matching)."""

    xy: float
    xy_step: float
    theta: float
    theta_step: float
    fine_xy: float
    fine_theta: float
    pool: int = 1
    candidates: int = 1
    penalty: tuple[float, float, float, float] | None = None
    refine: bool = True


@dataclass(frozen=True)
class MatchResult:
    pose: Pose2
    response: float
    covariance: np.ndarray
    """3x3 over (x, y, theta)."""

    @property
    def variance_xy(self) -> float:
        """The larger principal variance of the position (m²)."""
        return float(np.linalg.eigvalsh(self.covariance[:2, :2])[-1])


def _steps(half: float, step: float) -> np.ndarray:
    n = max(0, round(half / step))
    out: np.ndarray = np.arange(-n, n + 1) * step
    return out


def _lattice(center: np.ndarray, wxy: float, sxy: float, wth: float, sth: float) -> np.ndarray:
    d = _steps(wxy, sxy)
    t = _steps(wth, sth)
    gx, gy, gt = np.meshgrid(center[0] + d, center[1] + d, center[2] + t, indexing="ij")
    return np.column_stack([gx.ravel(), gy.ravel(), gt.ravel()])


def _penalised(scores: np.ndarray, poses: np.ndarray, guess: np.ndarray,
               penalty: tuple[float, float, float, float] | None) -> np.ndarray:
    if penalty is None:
        return scores
    dist_var, ang_var, min_dist, min_ang = penalty
    d2 = (poses[:, 0] - guess[0]) ** 2 + (poses[:, 1] - guess[1]) ** 2
    a2 = (poses[:, 2] - guess[2]) ** 2
    out: np.ndarray = (scores * np.maximum(1.0 - 0.2 * d2 / dist_var, min_dist)
                       * np.maximum(1.0 - 0.2 * a2 / ang_var, min_ang))
    return out


def _covariance(poses: np.ndarray, resp: np.ndarray, best: np.ndarray, best_resp: float,
                step: float, theta_step: float) -> np.ndarray:
    """Karto's estimate: the second moment about the best pose of the cells whose response
    is within 0.1 of the best, floored at a tenth of a coarse step squared, over the best."""
    cov = np.zeros((3, 3))
    near = resp >= best_resp - 0.1
    if best_resp <= 0 or not near.any():
        return np.diag([500.0, 500.0, 500.0])
    w = resp[near]
    d = poses[near] - best
    d[:, 2] = (d[:, 2] + np.pi) % (2 * np.pi) - np.pi
    wsum = float(w.sum())
    cov[:2, :2] = (d[:, :2].T * w) @ d[:, :2] / wsum
    cov[2, 2] = float((w * d[:, 2] ** 2).sum() / wsum)
    cov[0, 0] = max(cov[0, 0], 0.1 * step * step)
    cov[1, 1] = max(cov[1, 1], 0.1 * step * step)
    cov[2, 2] = max(cov[2, 2], 0.1 * theta_step * theta_step)
    cov[2, :2] = cov[:2, 2] = 0.0
    return cov / best_resp


def refine(grid: CorrelationGrid, pts: np.ndarray, start: np.ndarray, limit: float,
           iterations: int = 5) -> tuple[np.ndarray, float]:
    """Gauss-Newton on the bilinearly interpolated field (Hector's, Cartographer's last step):
    the pose near ``start`` (within ``limit`` metres) maximising the mean field under
    ``pts``, and that mean."""
    x = start.astype(np.float64).copy()
    px, py = pts[:, 0], pts[:, 1]
    best_x, best = x.copy(), float(grid.bilinear(pts, x)[0].mean())
    for _ in range(iterations):
        f, gu, gv = grid.bilinear(pts, x)
        c, s = math.cos(x[2]), math.sin(x[2])
        dth_x, dth_y = -s * px - c * py, c * px - s * py
        jac = np.column_stack([gu, gv, gu * dth_x + gv * dth_y])  # d f / d (x, y, theta)
        r = 1.0 - f
        h = jac.T @ jac
        h[np.diag_indices(3)] *= 1.01
        h[np.diag_indices(3)] += 1e-6
        try:
            step = np.linalg.solve(h, jac.T @ r)
        except np.linalg.LinAlgError:
            break
        trial = x + step
        if math.hypot(trial[0] - start[0], trial[1] - start[1]) > limit:
            break
        score = float(grid.bilinear(pts, trial)[0].mean())
        if score <= best:
            break
        x, best_x, best = trial, trial.copy(), score
        if np.abs(step).max() < 1e-4:
            break
    return best_x, float(best)


def match(grid: CorrelationGrid, pts: np.ndarray, guess: Pose2, win: Window,
          refine_pts: np.ndarray | None = None) -> MatchResult:
    """The best pose for scan points ``pts`` (base frame) within ``win`` round ``guess``.

    Coarse: whole-cell shifts every ``xy_step`` (on the max-pooled grid when ``pool``) at
    each heading step; then, for the best ``candidates``, every cell within the coarse cell
    at headings ±half a coarse step; last, sub-cell shifts of ``fine_xy`` and headings of
    ``fine_theta`` round the best; then `refine` (with ``refine_pts``, all the scan's
    points, if given).
    """
    g = np.array(guess, dtype=np.float64)
    if len(pts) < 3:
        return MatchResult(guess, 0.0, np.diag([500.0, 500.0, 500.0]))
    res = grid.res
    stride = max(1, round(win.xy_step / res))
    cells = max(1, round(win.xy / (stride * res)))
    pooled = win.pool > 1 and stride > 1
    coarse_grid = grid.pooled(stride) if pooled else grid
    thetas = g[2] + _steps(win.theta, win.theta_step)
    coarse, sc = coarse_grid.lattice_scores(pts, g, cells, stride, thetas)
    sc = _penalised(sc, coarse, g, win.penalty)
    cov_poses, cov_scores = coarse, sc
    order = np.argsort(sc)[::-1][:max(1, win.candidates)]
    best, best_resp = coarse[order[0]], -1.0
    for k in order:
        c = coarse[k].copy()
        if stride > 1:
            if pooled:  # the pooled cell bounds the shifts up/right of it
                c[:2] += (stride // 2) * res
            mid, ms = grid.lattice_scores(pts, c, stride // 2 + 1, 1,
                                          c[2] + _steps(win.theta_step / 2, win.fine_theta))
            ms = _penalised(ms, mid, g, win.penalty)
            i = int(np.argmax(ms))
            if ms[i] <= best_resp:
                continue
            c = mid[i]
            cov_poses, cov_scores = mid, ms
            fine_th = win.fine_theta
        else:
            fine_th = win.theta_step / 2
        fine = _lattice(c, res / 2, win.fine_xy, fine_th, win.fine_theta)
        sf = _penalised(grid.scores(pts, fine), fine, g, win.penalty)
        i = int(np.argmax(sf))
        if sf[i] > best_resp:
            best_resp, best = float(sf[i]), fine[i]
    if win.refine:
        best, refined = refine(grid, refine_pts if refine_pts is not None else pts, best, res)
        best_resp = max(best_resp, refined) if win.penalty is None else best_resp
    cov = _covariance(cov_poses, cov_scores, best, float(cov_scores.max()), stride * res,
                      win.theta_step)
    pose = Pose2(float(best[0]), float(best[1]), wrap_angle(float(best[2])))
    return MatchResult(pose, best_resp, cov)
