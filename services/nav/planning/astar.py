"""The search: 8-connected, cost-aware A* on a uint8 cost grid (the Python reference).

Costs are fixed-point integers (``FIXED`` = 2^20 per cell): a step into a cell of cost
byte ``c`` costs ``straight[c]`` or ``diag[c]`` (negative: the cell cannot be entered),
so sums are exact and the compiled search (``_astar.c``) repeats this one bit for bit.
The heuristic ``hs·max(dx, dy) + hd·min(dx, dy)`` is the octile distance scaled by the
cheapest step and rounded down, so it is admissible and consistent: the first time the
goal is taken from the open list its path is optimal for these step costs.

Open-list order: cells whose f equals the f last taken from the ordered part are kept on
a stack (each expansion pushes its own in descending (h, cell) order, so the one nearest
the goal comes next); the others are ordered by (f, h >> 10, cell). Both kinds of choice
take a cell of least f, which is all A* needs; the stack makes long runs of equal f (a
flooded corridor, an open plateau) cheap.
"""

from __future__ import annotations

import heapq
import time
from dataclasses import dataclass

import numpy as np

__all__ = ["FIXED", "FOUND", "LIMIT", "NO_PATH", "TIMEOUT", "SearchOutcome", "search_python"]

FIXED = 1 << 20
"""Fixed-point units per cell of travel."""
FOUND, NO_PATH, TIMEOUT, LIMIT = 0, 1, 2, 3
CHECK_EVERY = 1024
_DX = (1, -1, 0, 0, 1, 1, -1, -1)
_DY = (0, 0, 1, -1, 1, -1, 1, -1)
_TIE_MAX = 0xFFFFFFFF


@dataclass(frozen=True, slots=True)
class SearchOutcome:
    """What a search returns: a status, the flat cells goal → start, g at the goal."""

    status: int
    path: np.ndarray  # int32 flat indices, goal first
    g_goal: int  # fixed point
    expansions: int


def _tie(h: int, idx: int) -> int:
    return (min(h >> 10, _TIE_MAX) << 32) | idx


def search_python(
    costs: np.ndarray,
    steps: np.ndarray,
    start: int,
    goal: int,
    hs: int,
    hd: int,
    budget_s: float,
    max_expansions: int,
) -> SearchOutcome:
    """A* from flat cell ``start`` to ``goal`` over ``costs`` (2-D uint8, C order);
    ``steps``: 512 int64, the straight then diagonal step cost of each cost byte."""
    rows, w = int(costs.shape[0]), int(costs.shape[1])
    flat = costs.ravel().tolist()
    table = [int(v) for v in steps]
    straight, diag = table[:256], table[256:]
    gx, gy = goal % w, goal // w

    def octile(x: int, y: int) -> int:
        dx, dy = abs(x - gx), abs(y - gy)
        return hs * dy + hd * dx if dx < dy else hs * dx + hd * dy

    deadline = time.monotonic() + budget_s if budget_s > 0 else 0.0
    g: dict[int, int] = {start: 0}
    parent: dict[int, int] = {start: -1}
    closed: set[int] = set()
    h0 = octile(start % w, start // w)
    heap: list[tuple[int, int]] = [(h0, _tie(h0, start))]
    stack: list[int] = []
    cur_f = -1
    n_exp = 0
    status = NO_PATH
    while stack or heap:
        if stack:
            cur = stack.pop()
        else:
            cur_f, tie = heapq.heappop(heap)
            cur = tie & _TIE_MAX
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
        same: list[tuple[int, int]] = []
        for k in range(8):
            nx, ny = x + _DX[k], y + _DY[k]
            if nx < 0 or ny < 0 or nx >= w or ny >= rows:
                continue
            nb = ny * w + nx
            if nb in closed:
                continue
            step = straight[flat[nb]] if k < 4 else diag[flat[nb]]
            if step < 0:
                continue
            ng = gc + step
            old = g.get(nb)
            if old is not None and ng >= old:
                continue
            g[nb] = ng
            parent[nb] = cur
            hn = octile(nx, ny)
            if ng + hn == cur_f:
                same.append((hn, nb))
            else:
                heapq.heappush(heap, (ng + hn, _tie(hn, nb)))
        if same:
            same.sort(reverse=True)  # descending (h, cell): the smallest ends on top
            stack.extend(nb for _, nb in same)
    if status != FOUND:
        return SearchOutcome(status, np.empty(0, np.int32), 0, n_exp)
    path: list[int] = []
    c = goal
    while c != -1:
        path.append(c)
        c = parent[c]
    return SearchOutcome(status, np.array(path, dtype=np.int32), g[goal], n_exp)
