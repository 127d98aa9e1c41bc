"""The search: 8-connected, cost-aware A* on a uint8 cost grid (the Python reference).

Each step into a cell of cost ``c`` costs ``mult[c]`` (× √2 diagonally); a cost whose
multiplier is infinite (or negative) cannot be entered. The heuristic is the octile
distance times the smallest multiplier, which is admissible and consistent, so the first
time the goal is taken from the open list its path is optimal on the 8-connected grid.
The open list is ordered by (f, h, cell index): ties go to the cell nearer the goal, and
the whole order is total, so this code and the compiled one (``_astar.c``, the same
arithmetic) expand the same cells and return the same path.
"""

from __future__ import annotations

import heapq
import math
import time
from dataclasses import dataclass

import numpy as np

__all__ = ["FOUND", "LIMIT", "NO_PATH", "TIMEOUT", "SearchOutcome", "search_python"]

FOUND, NO_PATH, TIMEOUT, LIMIT = 0, 1, 2, 3
SQRT2 = 1.4142135623730951
CHECK_EVERY = 1024
_DX = (1, -1, 0, 0, 1, 1, -1, -1)
_DY = (0, 0, 1, -1, 1, -1, 1, -1)


@dataclass(frozen=True, slots=True)
class SearchOutcome:
    """What a search returns: a status, the flat cells goal → start, g at the goal."""

    status: int
    path: np.ndarray  # int32 flat indices, goal first
    g_goal: float
    expansions: int


def _octile(x: int, y: int, gx: int, gy: int, scale: float) -> float:
    dx = abs(x - gx)
    dy = abs(y - gy)
    lo, hi = (dx, dy) if dx < dy else (dy, dx)
    return scale * (float(hi) + (SQRT2 - 1.0) * float(lo))


def search_python(
    costs: np.ndarray,
    mult: np.ndarray,
    start: int,
    goal: int,
    h_scale: float,
    budget_s: float,
    max_expansions: int,
) -> SearchOutcome:
    """A* from flat cell ``start`` to ``goal`` over ``costs`` (2-D uint8, C order)."""
    h_rows, w = costs.shape
    flat = costs.ravel().tolist()
    m = [float(v) for v in mult]
    passable = [(v >= 0.0) and not math.isinf(v) for v in m]
    gx, gy = goal % w, goal // w
    deadline = time.monotonic() + budget_s if budget_s > 0 else 0.0
    g: dict[int, float] = {start: 0.0}
    parent: dict[int, int] = {start: -1}
    closed: set[int] = set()
    h0 = _octile(start % w, start // w, gx, gy, h_scale)
    heap: list[tuple[float, float, int]] = [(0.0 + h0, h0, start)]
    n_exp = 0
    status = NO_PATH
    while heap:
        _, _, cur = heapq.heappop(heap)
        if cur in closed:
            continue  # a stale entry: the cell was closed with a better g
        closed.add(cur)
        if cur == goal:
            status = FOUND
            break
        n_exp += 1
        if max_expansions > 0 and n_exp > max_expansions:
            status = LIMIT
            break
        if deadline > 0 and n_exp % CHECK_EVERY == 0 and time.monotonic() > deadline:
            status = TIMEOUT
            break
        x, y = cur % w, cur // w
        gc = g[cur]
        for k in range(8):
            nx, ny = x + _DX[k], y + _DY[k]
            if nx < 0 or ny < 0 or nx >= w or ny >= h_rows:
                continue
            nb = ny * w + nx
            if nb in closed:
                continue
            c = flat[nb]
            if not passable[c]:
                continue
            step = m[c] if k < 4 else m[c] * SQRT2
            ng = gc + step
            old = g.get(nb)
            if old is not None and not ng < old:
                continue
            g[nb] = ng
            parent[nb] = cur
            hn = _octile(nx, ny, gx, gy, h_scale)
            heapq.heappush(heap, (ng + hn, hn, nb))
    if status != FOUND:
        return SearchOutcome(status, np.empty(0, np.int32), 0.0, n_exp)
    path: list[int] = []
    c = goal
    while c != -1:
        path.append(c)
        c = parent[c]
    return SearchOutcome(status, np.array(path, dtype=np.int32), g[goal], n_exp)
