"""Pose-graph optimisation on SE(2): Levenberg-Marquardt with scipy.sparse (specs/mapping.md, section 7).

The residual of an edge i→j with measurement z is Karto/Ceres's
``[R(θi)ᵀ(pj − pi) − z_xy; wrap(θj − θi − zθ)]``, weighted by the upper Cholesky factor
of its information. The first node is held fixed (the map frame). Loop edges get a Huber
weight (iteratively reweighted), so a bad closure pulls less than a good one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import spsolve

from .graph import Edge

__all__ = ["OptimizeResult", "optimize"]


@dataclass(frozen=True)
class OptimizeResult:
    poses: np.ndarray
    iterations: int
    initial_cost: float
    final_cost: float


def _wrap(a: np.ndarray) -> np.ndarray:
    out: np.ndarray = (a + np.pi) % (2 * np.pi) - np.pi
    return out


def _residuals(x: np.ndarray, ii: np.ndarray, jj: np.ndarray, z: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Residuals (m, 3) and the Jacobian blocks' varying parts."""
    pi, pj = x[ii], x[jj]
    c, s = np.cos(pi[:, 2]), np.sin(pi[:, 2])
    dx, dy = pj[:, 0] - pi[:, 0], pj[:, 1] - pi[:, 1]
    e = np.empty((len(ii), 3))
    e[:, 0] = c * dx + s * dy - z[:, 0]
    e[:, 1] = -s * dx + c * dy - z[:, 1]
    e[:, 2] = _wrap(pj[:, 2] - pi[:, 2] - z[:, 2])
    return e, c, s, np.column_stack([-s * dx + c * dy, -c * dx - s * dy])


def optimize(poses: np.ndarray, edges: list[Edge], iterations: int = 20,
             huber: float = 3.0, tolerance: float = 1e-6) -> OptimizeResult:
    """Optimised copies of ``poses`` (n, 3) under ``edges``; node 0 fixed."""
    x = np.array(poses, dtype=np.float64)
    n, m = len(x), len(edges)
    if n < 2 or m == 0:
        return OptimizeResult(x, 0, 0.0, 0.0)
    ii = np.array([e.i for e in edges])
    jj = np.array([e.j for e in edges])
    z = np.array([e.z for e in edges], dtype=np.float64)
    loop = np.array([e.kind == "loop" for e in edges])
    # upper Cholesky factors: info = Uᵀ U
    sqrt_info = np.array([np.linalg.cholesky(e.information).T for e in edges])

    def cost_of(xv: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        e, c, s, d = _residuals(xv, ii, jj, z)
        we = np.einsum("kab,kb->ka", sqrt_info, e)
        norm = np.linalg.norm(we, axis=1)
        w = np.ones(m)
        big = loop & (norm > huber)
        w[big] = huber / norm[big]
        return float(np.sum(w * norm ** 2)), we, w

    lam = 1e-4
    cost, _, _ = cost_of(x)
    initial = cost
    it = 0
    rows = np.repeat(np.arange(3 * m).reshape(m, 3), 6, axis=1).ravel()
    for it in range(1, iterations + 1):
        e, c, s, d = _residuals(x, ii, jj, z)
        _, we, w = cost_of(x)
        # raw Jacobian blocks (m, 3, 3) for i and j
        ji = np.zeros((m, 3, 3))
        ji[:, 0, 0], ji[:, 0, 1], ji[:, 0, 2] = -c, -s, d[:, 0]
        ji[:, 1, 0], ji[:, 1, 1], ji[:, 1, 2] = s, -c, d[:, 1]
        ji[:, 2, 2] = -1.0
        jj_ = np.zeros((m, 3, 3))
        jj_[:, 0, 0], jj_[:, 0, 1] = c, s
        jj_[:, 1, 0], jj_[:, 1, 1] = -s, c
        jj_[:, 2, 2] = 1.0
        sw = np.sqrt(w)[:, None, None]
        wi = sw * np.einsum("kab,kbc->kac", sqrt_info, ji)
        wj = sw * np.einsum("kab,kbc->kac", sqrt_info, jj_)
        vals = np.concatenate([wi, wj], axis=2).ravel()
        cols = np.concatenate([3 * ii[:, None] + np.arange(3), 3 * jj[:, None] + np.arange(3)],
                              axis=1)
        cols = np.repeat(cols[:, None, :], 3, axis=1).ravel()
        jac = sparse.csr_matrix((vals, (rows, cols)), shape=(3 * m, 3 * n))[:, 3:]
        r = (np.sqrt(w)[:, None] * we).ravel()
        h = (jac.T @ jac).tocsc()
        g = jac.T @ r
        diag = h.diagonal()
        while True:
            step = spsolve(h + sparse.diags(lam * (diag + 1e-9)), -g)
            trial = x.copy()
            trial[1:] += step.reshape(-1, 3)
            trial[:, 2] = _wrap(trial[:, 2])
            new_cost, _, _ = cost_of(trial)
            if new_cost <= cost:
                x, lam = trial, max(lam / 10, 1e-9)
                break
            lam *= 10
            if lam > 1e6:
                return OptimizeResult(x, it, initial, cost)
        done = abs(cost - new_cost) <= tolerance * max(cost, 1e-12) or np.abs(step).max() < 1e-7
        cost = new_cost
        if done:
            break
    return OptimizeResult(x, it, initial, cost)
