"""`Chain`: the cached path between two frames, evaluated without walking the tree.

tf2 walks the tree on every lookup. Here the path from ``source`` and from ``target`` up to
their common ancestor is found once and kept until the tree's shape changes (a new link, a
re-parenting, a static change, ``clear()``). Runs of static links are composed in advance.
A lookup then costs one bisect and a few float operations per dynamic link.

A chain is only built when every link on the way is static or holds samples that all share
one parent; otherwise (re-parenting inside the window, empty caches, no common ancestor)
the buffer walks the tree as tf2 does (``walk``). When evaluation fails (no data at ``t``),
the caller re-runs the walk to raise tf2's exact error.
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable, Mapping
from math import cos, sin

from .accel import speedups
from .cache import Cache, Seg, StaticCache, TimeCache
from .rigid import IDENTITY, Tf, compose

# One dynamic link: its stamps and segments (the cache's own lists), the cache, and the
# static run composed on top of it (or None).
Step = tuple[list[int], list[Seg | None], TimeCache, Tf | None]

__all__ = ["DISJOINT", "WALK", "Chain", "NoChain", "build_chain"]

_c_evaluate: Callable[[Tf | None, list[Step], Tf | None, list[Step], int], Tf | None] | None
_c_evaluate = speedups.evaluate if speedups is not None else None
_c_latest: Callable[[list[list[int]]], int] | None
_c_latest = speedups.latest if speedups is not None else None


class Chain:
    """The links between two frames and their common ancestor, ready to evaluate."""

    __slots__ = ("caches", "dyn", "src", "src_pre", "tgt", "tgt_pre")

    def __init__(
        self, src_pre: Tf | None, src: list[Step], tgt_pre: Tf | None, tgt: list[Step]
    ) -> None:
        self.src_pre, self.src, self.tgt_pre, self.tgt = src_pre, src, tgt_pre, tgt
        self.dyn = [s[0] for s in src] + [s[0] for s in tgt]
        self.caches = [s[2] for s in src] + [s[2] for s in tgt]

    def latest_time(self) -> int:
        """The latest common time: the oldest of the dynamic links' newest stamps (0: static)."""
        if _c_latest is not None:
            return _c_latest(self.dyn)
        return min([s[-1] for s in self.dyn]) if self.dyn else 0

    def covers(self, t: int) -> bool:
        """Whether every dynamic link has data at ``t`` (exact stamp or bracketed)."""
        for c in self.caches:
            s = c.stamps
            if not s[c.lo] <= t <= s[-1]:
                return False
        return True

    def evaluate(self, t: int) -> Tf | None:
        """``T_target_source`` at ``t`` (ns, not 0), or None if a link has no data there."""
        if _c_evaluate is not None:
            return _c_evaluate(self.src_pre, self.src, self.tgt_pre, self.tgt, t)
        return self.evaluate_py(t)

    def evaluate_py(self, t: int) -> Tf | None:
        """`evaluate` in Python: the reference for the compiled version."""
        src = _accumulate(self.src_pre, self.src, t)
        if src is None or not (self.tgt or self.tgt_pre):
            return src
        tgt = _accumulate(self.tgt_pre, self.tgt, t)
        if tgt is None:
            return None
        # inverse(tgt) ∘ src: rotate (src.t − tgt.t) by conj(tgt.q); q = conj(tgt.q)·src.q
        x, y, z = src[0] - tgt[0], src[1] - tgt[1], src[2] - tgt[2]
        qx, qy, qz, qw = -tgt[3], -tgt[4], -tgt[5], tgt[6]
        rx, ry, rz, rw = src[3], src[4], src[5], src[6]
        tx = 2.0 * (qy * z - qz * y)
        ty = 2.0 * (qz * x - qx * z)
        tz = 2.0 * (qx * y - qy * x)
        return (
            x + qw * tx + qy * tz - qz * ty,
            y + qw * ty + qz * tx - qx * tz,
            z + qw * tz + qx * ty - qy * tx,
            qw * rx + qx * rw + qy * rz - qz * ry,
            qw * ry - qx * rz + qy * rw + qz * rx,
            qw * rz + qx * ry - qy * rx + qz * rw,
            qw * rw - qx * rx - qy * ry - qz * rz,
        )


def _accumulate(pre: Tf | None, steps: list[Step], t: int) -> Tf | None:
    """Compose the links from the bottom up, ``A ← post ∘ T_i(t) ∘ A``; None if one has no
    data at ``t``. Hot path: the interpolation is written out twice (first link, loop)."""
    it = iter(steps)
    if pre is None:  # the first link is the accumulator: no composition needed
        for stamps, segs, cache, post in it:
            lo = cache.lo
            i = bisect_right(stamps, t, lo)
            if i > lo and t < stamps[-1]:
                seg = segs[i - 1] or cache.segment(i - 1)
                s0, idt, X, Y, Z, dx, dy, dz, ax, ay, az, aw, cx, cy, cz, cw, th = seg
                r = (t - s0) * idt
                X += r * dx
                Y += r * dy
                Z += r * dz
                c, s = cos(r * th), sin(r * th)
                QX, QY, QZ, QW = c * ax + s * cx, c * ay + s * cy, c * az + s * cz, c * aw + s * cw
            elif i > lo and t == stamps[-1]:
                X, Y, Z, QX, QY, QZ, QW = cache.vals[-1]
            else:
                return None
            if post is not None:
                X, Y, Z, QX, QY, QZ, QW = compose(post, (X, Y, Z, QX, QY, QZ, QW))
            break
        else:
            return IDENTITY
    else:
        X, Y, Z, QX, QY, QZ, QW = pre
    for stamps, segs, cache, post in it:
        lo = cache.lo
        i = bisect_right(stamps, t, lo)
        if i > lo and t < stamps[-1]:
            seg = segs[i - 1] or cache.segment(i - 1)
            s0, idt, x, y, z, dx, dy, dz, ax, ay, az, aw, cx, cy, cz, cw, th = seg
            r = (t - s0) * idt
            x += r * dx
            y += r * dy
            z += r * dz
            c, s = cos(r * th), sin(r * th)
            qx, qy, qz, qw = c * ax + s * cx, c * ay + s * cy, c * az + s * cz, c * aw + s * cw
        elif i > lo and t == stamps[-1]:
            x, y, z, qx, qy, qz, qw = cache.vals[-1]
        else:
            return None
        # A ← T ∘ A: rotate A's translation by q and add T's; Q ← q·Q
        tx = 2.0 * (qy * Z - qz * Y)
        ty = 2.0 * (qz * X - qx * Z)
        tz = 2.0 * (qx * Y - qy * X)
        X, Y, Z, QX, QY, QZ, QW = (
            x + X + qw * tx + qy * tz - qz * ty,
            y + Y + qw * ty + qz * tx - qx * tz,
            z + Z + qw * tz + qx * ty - qy * tx,
            qw * QX + qx * QW + qy * QZ - qz * QY,
            qw * QY - qx * QZ + qy * QW + qz * QX,
            qw * QZ + qx * QY - qy * QX + qz * QW,
            qw * QW - qx * QX - qy * QY - qz * QZ,
        )
        if post is not None:
            X, Y, Z, QX, QY, QZ, QW = compose(post, (X, Y, Z, QX, QY, QZ, QW))
    return (X, Y, Z, QX, QY, QZ, QW)


def _steps(links: list[Cache]) -> tuple[Tf | None, list[Step]]:
    """Turn links (bottom up) into dynamic steps, composing static runs in advance."""
    pre: Tf | None = None
    steps: list[Step] = []
    pending: Tf | None = None
    for c in links:
        if isinstance(c, StaticCache):
            pending = c.value if pending is None else compose(c.value, pending)
            continue
        if steps:
            last = steps[-1]
            steps[-1] = (last[0], last[1], last[2], pending)
        else:
            pre = pending
        pending = None
        steps.append((c.stamps, c.segs, c, None))
    if steps:
        last = steps[-1]
        steps[-1] = (last[0], last[1], last[2], pending)
    else:
        pre = pending
    return pre, steps


class NoChain:
    """Why a pair has no chain (falsy): the walk must answer, or the trees are disjoint."""

    __slots__ = ("disjoint",)

    def __init__(self, disjoint: bool) -> None:
        self.disjoint = disjoint

    def __bool__(self) -> bool:
        return False


WALK = NoChain(False)
"""Re-parenting inside the window, an empty link or a loop: only the tf2 walk can answer."""
DISJOINT = NoChain(True)
"""The frames are in different trees at every time: no transform, whatever the time."""


def build_chain(
    caches: Mapping[str, Cache], target: str, source: str, limit: int
) -> Chain | NoChain:
    """The chain between two known frames, or why there is none."""
    pos = {source: 0}
    up: list[Cache] = []
    frame = source
    while (cache := caches.get(frame)) is not None:
        parent = cache.parent
        if parent is None or parent in pos or len(up) >= limit:
            return WALK  # mixed parents, empty, or a loop
        up.append(cache)
        pos[parent] = len(up)
        frame = parent
    down: list[Cache] = []
    frame = target
    while frame not in pos:
        cache = caches.get(frame)
        if cache is None:
            return DISJOINT  # target's root is not among source's ancestors
        if cache.parent is None or len(down) >= limit:
            return WALK
        down.append(cache)
        frame = cache.parent
    src_pre, src = _steps(up[: pos[frame]])
    tgt_pre, tgt = _steps(down)
    return Chain(src_pre, src, tgt_pre, tgt)
