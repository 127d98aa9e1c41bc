"""Per-frame link storage: `TimeCache` (a time window of samples) and `StaticCache` (one slot).

A cache belongs to a child frame and stores ``T_parent_child`` samples, each with its parent
id (the parent may change over time). Stamps are integer nanoseconds.
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from math import acos, cos, sin

from ..errors import (
    BackwardExtrapolationException,
    ForwardExtrapolationException,
    NoDataForExtrapolationException,
)
from .rigid import Tf
from .stamps import format_ns

# A segment holds what interpolating between samples i and i+1 needs, computed once:
# (s0, 1/dt, x0, y0, z0, dx, dy, dz, ax, ay, az, aw, cx, cy, cz, cw, theta).
# Rotation: slerp(a, b, r) = cos(rθ)·a + sin(rθ)·c, where c is the unit quaternion
# orthogonal to a in the plane of a and b (b negated first when dot(a, b) < 0, so the short
# arc is taken) and θ the angle between them; θ = 0 gives c = 0, i.e. a throughout.
Seg = tuple[
    int, float, float, float, float, float, float, float,
    float, float, float, float, float, float, float, float, float,
]  # fmt: skip

COMPACT_AT = 32
"""A cache deletes its pruned samples once there are this many and no fewer live ones."""

REJECTED = 0
"""`insert` result: the sample is older than the window allows (tf2's TF_OLD_DATA)."""
STORED = 1
"""`insert` result: stored; the link's parent structure did not change."""
RESHAPED = 2
"""`insert` result: stored, and the link's parent structure changed (new, re-parented...)."""

__all__ = ["COMPACT_AT", "REJECTED", "RESHAPED", "STORED", "Seg", "StaticCache", "TimeCache", "make_segment"]


def make_segment(s0: int, s1: int, a: Tf, b: Tf) -> Seg:
    """Interpolation constants between sample ``a`` at ``s0`` and sample ``b`` at ``s1``."""
    ax, ay, az, aw = float(a[3]), float(a[4]), float(a[5]), float(a[6])
    bx, by, bz, bw = float(b[3]), float(b[4]), float(b[5]), float(b[6])
    d = ax * bx + ay * by + az * bz + aw * bw
    if d < 0.0:
        bx, by, bz, bw, d = -bx, -by, -bz, -bw, -d
    theta = acos(min(d, 1.0))
    if theta != 0.0:
        k = 1.0 / sin(theta)
        c = ((bx - d * ax) * k, (by - d * ay) * k, (bz - d * az) * k, (bw - d * aw) * k)
    else:
        c = (0.0, 0.0, 0.0, 0.0)
    x, y, z = float(a[0]), float(a[1]), float(a[2])
    return (
        s0, 1.0 / (s1 - s0), x, y, z, float(b[0]) - x, float(b[1]) - y, float(b[2]) - z,
        ax, ay, az, aw, *c, theta,
    )  # fmt: skip


def interpolate_segment(seg: Seg, t: int) -> Tf:
    """The transform at ``t`` within a segment: linear translation, short-arc slerp."""
    s0, idt, x, y, z, dx, dy, dz, ax, ay, az, aw, cx, cy, cz, cw, th = seg
    r = (t - s0) * idt
    c, s = cos(r * th), sin(r * th)
    return (
        x + r * dx, y + r * dy, z + r * dz,
        c * ax + s * cx, c * ay + s * cy, c * az + s * cz, c * aw + s * cw,
    )  # fmt: skip


class TimeCache:
    """A dynamic link's samples within ``cache_ns`` of its newest one, sorted by stamp.

    Lists are oldest first and are only ever mutated in place, so a cached chain may hold
    references to them. Inserting at the newest end is O(1), out of order O(log n) to find
    plus a list insert; a sample with an existing stamp replaces it (last writer wins).
    Pruning happens after each insert, against the new newest stamp (ROS 1 behaviour).

    Pruned samples leave lazily: the live ones start at index ``lo``, and the dead prefix
    is deleted once it is as long as the rest (amortised O(1): ``del lst[:1]`` moves the
    whole list, 80 kB per list for a 10 s window at 1 kHz, on every insert).
    """

    __slots__ = ("_breaks", "cache_ns", "lo", "parent", "parents", "segs", "stamps", "vals")
    is_static = False

    def __init__(self, cache_ns: int) -> None:
        self.cache_ns = cache_ns
        self.stamps: list[int] = []
        self.vals: list[Tf] = []
        self.parents: list[str] = []
        self.segs: list[Seg | None] = []  # segs[i]: samples i → i+1; the last slot is unused
        self.parent: str | None = None  # the parent shared by every sample, else None
        self._breaks = 0  # adjacent live samples with different parents
        self.lo = 0  # the index of the oldest live sample; those before it are pruned

    def __len__(self) -> int:
        return len(self.stamps) - self.lo

    def insert(self, stamp: int, parent: str, val: Tf) -> int:
        """Store one sample; returns `REJECTED`, `STORED` or `RESHAPED`."""
        stamps, parents = self.stamps, self.parents
        n = len(stamps)
        if n and stamp > stamps[-1]:
            stamps.append(stamp)
            self.vals.append(val)
            self.segs.append(None)
            if parent != parents[-1]:
                self._breaks += 1
            parents.append(parent)
        elif not n:
            stamps.append(stamp)
            self.vals.append(val)
            self.segs.append(None)
            parents.append(parent)
        elif stamp < stamps[-1] - self.cache_ns:
            return REJECTED
        else:
            self._insert_inside(bisect_left(stamps, stamp, self.lo), stamp, parent, val)
        if stamps[self.lo] < stamps[-1] - self.cache_ns:
            self.prune()
        shape = parents[self.lo] if self._breaks == 0 else None
        if shape == self.parent:
            return STORED
        self.parent = shape
        return RESHAPED

    def _insert_inside(self, i: int, stamp: int, parent: str, val: Tf) -> None:
        stamps, parents, segs = self.stamps, self.parents, self.segs
        if stamps[i] == stamp:  # same stamp: replace
            self._breaks -= self._breaks_around(i)
            parents[i] = parent
            self.vals[i] = val
            segs[i] = None
        else:
            if i > self.lo and parents[i - 1] != parents[i]:
                self._breaks -= 1
            stamps.insert(i, stamp)
            parents.insert(i, parent)
            self.vals.insert(i, val)
            segs.insert(i, None)
        if i > 0:
            segs[i - 1] = None
        self._breaks += self._breaks_around(i)

    def _breaks_around(self, i: int) -> int:
        parents = self.parents
        p = parents[i]
        return (i > self.lo and parents[i - 1] != p) + (
            i + 1 < len(parents) and parents[i + 1] != p
        )

    def prune(self) -> None:
        """Drop the samples older than the newest minus the window (strictly older)."""
        stamps, parents, lo = self.stamps, self.parents, self.lo
        cutoff = stamps[-1] - self.cache_ns
        # steady rate: exactly one sample fell out of the window
        k = lo + 1 if stamps[lo + 1] >= cutoff else bisect_left(stamps, cutoff, lo)
        if self._breaks:
            self._breaks -= sum(1 for j in range(lo, k) if parents[j] != parents[j + 1])
        if k >= COMPACT_AT and 2 * k >= len(stamps):
            del stamps[:k], self.vals[:k], parents[:k], self.segs[:k]
            k = 0
        self.lo = k

    def clear(self) -> bool:
        """Drop every sample; True if there were any."""
        had = bool(self.stamps)
        for lst in (self.stamps, self.vals, self.parents, self.segs):
            lst.clear()
        self.parent, self._breaks, self.lo = None, 0, 0
        return had

    def segment(self, i: int) -> Seg:
        """The (cached) interpolation constants between samples ``i`` and ``i + 1``."""
        seg = self.segs[i]
        if seg is None:
            seg = make_segment(self.stamps[i], self.stamps[i + 1], self.vals[i], self.vals[i + 1])
            self.segs[i] = seg
        return seg

    def latest(self) -> tuple[int, str] | None:
        """``(newest stamp, its parent)``, or None when empty."""
        if not self.stamps:
            return None
        return self.stamps[-1], self.parents[-1]

    def newest(self) -> int:
        """The newest stamp (0 when empty)."""
        return self.stamps[-1] if self.stamps else 0

    def oldest(self) -> int:
        """The oldest stamp (0 when empty)."""
        return self.stamps[self.lo] if self.stamps else 0

    def parent_at(self, t: int) -> str | None:
        """The parent a lookup at ``t`` would follow (outside the data: the nearest sample's)."""
        if not self.stamps:
            return None
        if t == 0:
            return self.parents[-1]
        lo = self.lo
        return self.parents[max(bisect_right(self.stamps, t, lo) - 1, lo)]

    def get(self, t: int) -> tuple[Tf, str]:
        """The link at ``t`` and its parent, as tf2's ``TimeCache::getData`` finds them.

        Raises:
            NoDataForExtrapolationException: empty, or one sample at another stamp.
            ForwardExtrapolationException: ``t`` is newer than the newest sample.
            BackwardExtrapolationException: ``t`` is older than the oldest sample.
        """
        stamps = self.stamps
        if not stamps:
            raise NoDataForExtrapolationException(
                f"Lookup would require extrapolation at time {format_ns(t)}, "
                f"but only time {format_ns(0)} is in the buffer"
            )
        if t == 0 or t == stamps[-1]:
            return self.vals[-1], self.parents[-1]
        lo = self.lo
        if len(stamps) - lo == 1:
            raise NoDataForExtrapolationException(
                f"Lookup would require extrapolation at time {format_ns(t)}, "
                f"but only time {format_ns(stamps[lo])} is in the buffer"
            )
        if t == stamps[lo]:
            return self.vals[lo], self.parents[lo]
        if t > stamps[-1]:
            raise ForwardExtrapolationException(
                "Lookup would require extrapolation into the future.  Requested time "
                f"{format_ns(t)} but the latest data is at time {format_ns(stamps[-1])}"
            )
        if t < stamps[lo]:
            raise BackwardExtrapolationException(
                "Lookup would require extrapolation into the past.  Requested time "
                f"{format_ns(t)} but the earliest data is at time {format_ns(stamps[lo])}"
            )
        i = bisect_right(stamps, t, lo) - 1
        if self.parents[i] != self.parents[i + 1]:  # re-parented in between: no interpolation
            return self.vals[i], self.parents[i]
        return interpolate_segment(self.segment(i), t), self.parents[i]


class StaticCache:
    """A static link: one slot, valid at every time, never pruned, untouched by ``clear()``."""

    __slots__ = ("parent", "value")
    is_static = True

    def __init__(self, parent: str, value: Tf) -> None:
        self.parent: str | None = parent
        self.value = value

    def __len__(self) -> int:
        return 1

    def insert(self, stamp: int, parent: str, val: Tf) -> int:
        """Overwrite the slot; `RESHAPED` when the parent or the value changed."""
        if parent == self.parent and val == self.value:
            return STORED
        self.parent, self.value = parent, val
        return RESHAPED

    def clear(self) -> bool:
        """No-op, as in tf2: statics survive ``Buffer.clear()``."""
        return False

    def latest(self) -> tuple[int, str] | None:
        """``(0, parent)``: statics never hold back the latest common time."""
        return 0, self.parent or ""

    def newest(self) -> int:
        """Always 0."""
        return 0

    def oldest(self) -> int:
        """Always 0."""
        return 0

    def parent_at(self, t: int) -> str | None:
        """The parent (time does not matter)."""
        return self.parent

    def get(self, t: int) -> tuple[Tf, str]:
        """The stored link, whatever ``t``."""
        return self.value, self.parent or ""


Cache = TimeCache | StaticCache
