"""TrafficTable: the reservation table of the schedule manager, in space and time.

A robot in schedule mode submits its route (points in ``map`` with the seconds from now
it expects to reach each); the table answers how far along it the robot may drive. Wide
segments (`segments.SegmentMap`) are never reserved: robots pass each other there. A
narrow segment is held by one robot at a time, from its grant until the robot's route no
longer holds it (it drove out) or its lease runs out.

Grants, in route order, up to ``horizon`` seconds ahead:

- **Chains.** A narrow segment is granted together with every narrow segment after it up
  to the next *passing place* (``passing_length`` metres of the route in wide segments, or
  the route's end), all or nothing. A robot that holds a narrow segment therefore never has
  to stop before it has left it, so holders wait for nobody and waiting robots hold
  nothing ahead of them: the wait-for graph has no cycle (deadlock-free by construction).
- **First come, first served.** A robot refused a segment joins its queue, ordered by when
  it first asked for the segment, then by name; a freed segment goes to the head of its
  queue, not to whoever asks next.
- **The passing place.** A refused robot's grant ends ``stand_off`` metres of route before
  the chain it waits for, so it waits in the wide segment before it, out of the mouth the
  oncoming robot comes out of.
- **Stepping aside.** A waiting robot that stands, or would stop, where the robot it waits
  for will drive (that robot's route cells and their neighbours) is sent to the nearest
  clear wide cell off that route instead (``yield_to`` with ``step_aside``), and waits
  there: the robot coming out of the narrow segment passes it instead of brushing it.
- **Leases.** Every request renews the robot's lease (``lease`` seconds); `expire` drops a
  robot whose lease ran out, with everything it held and its places in the queues.

What the chains cannot prevent: two robots *inside* the same narrow segment (one entered
without a grant: schedule mode started there, or a detour off its route), or a robot
inside a narrow segment waiting for another's that waits for it. `request` finds these
(a cycle of waiters, or a segment held by two) and tells the robot of lower priority (the
one that came later, then the greater name) to yield: its answer names the nearest
passing place behind it (``yield_to``) and it holds nothing until it asks again from there.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from .segments import SegmentMap

__all__ = ["Grant", "Hold", "RoutePoint", "TrafficError", "TrafficTable"]


class TrafficError(ValueError):
    """A request the table cannot take (a malformed route, a bad lease)."""


@dataclass(frozen=True)
class RoutePoint:
    """A point of a route in ``map`` and the seconds from now the robot expects to be there."""

    x: float
    y: float
    t: float = 0.0


@dataclass(frozen=True)
class Hold:
    """A narrow segment a robot holds, and when it expects to be in it (seconds of the
    table's clock)."""

    segment: int
    t_enter: float
    t_exit: float


@dataclass(frozen=True)
class Grant:
    """The answer to a route: drive route points ``[0, stop_index)``.

    ``granted`` is true when nothing on the route (up to the horizon) is refused; else
    ``stop`` is where to wait and ``wait_for`` whom for. ``yield_to`` (with ``must_yield``)
    is a passing place to back off to; with ``step_aside`` (a wait), the place off the
    route of ``wait_for`` to wait at.
    """

    robot: str
    granted: bool
    stop_index: int
    stop: tuple[float, float] | None
    wait_for: str
    holds: tuple[Hold, ...]
    expires: float
    must_yield: bool = False
    yield_to: tuple[float, float] | None = None
    step_aside: bool = False


@dataclass
class _Robot:
    name: str
    since: float  # first request: its priority (earlier first)
    expires: float
    holds: dict[int, Hold] = field(default_factory=dict)
    waiting: tuple[int, ...] = ()  # the chain it waits for
    wait_for: str = ""
    inside: int = -1  # the narrow segment it stands in (-1: a wide one)
    route_cells: frozenset[tuple[int, int]] = frozenset()
    position: tuple[float, float] = (math.nan, math.nan)
    last: Grant | None = None


@dataclass(frozen=True)
class _Visit:
    segment: int
    first: int  # route index where the route enters it
    last: int  # last route index in it
    s_first: float  # route length up to ``first``
    s_last: float


class TrafficTable:
    """The reservations on one `SegmentMap`; the clock is the caller's (``now`` seconds)."""

    def __init__(self, segments: SegmentMap, *, horizon: float = 15.0, stand_off: float = 0.9,
                 passing_length: float = 1.5, max_lease: float = 30.0,
                 max_route: int = 5000) -> None:
        self.map = segments
        self.horizon, self.stand_off = horizon, stand_off
        self.passing_length, self.max_lease, self.max_route = passing_length, max_lease, max_route
        self.robots: dict[str, _Robot] = {}
        self.holders: dict[int, set[str]] = {}
        self.queues: dict[int, list[tuple[float, str]]] = {}
        self.version = 0  # bumped by every change of the reservations

    # ------------------------------------------------------------------ requests

    def request(self, robot: str, route: Sequence[RoutePoint], now: float,
                lease: float) -> Grant:
        """Take ``robot``'s route (its first point is where it is) and answer its grant.

        Raises:
            TrafficError: an empty name, an empty, too long or non-finite route, or a lease
                that is not in (0, ``max_lease``].
        """
        self._check(robot, route, lease)
        self.expire(now)
        r = self.robots.get(robot)
        if r is None:
            r = self.robots[robot] = _Robot(robot, now, now + lease)
        r.expires = now + lease
        r.position = (route[0].x, route[0].y)
        xy = np.array([[p.x, p.y] for p in route], dtype=float)
        ts = np.array([p.t for p in route], dtype=float)
        visits = self._visits(xy)
        before = (dict(r.holds), r.waiting, r.wait_for)
        grant = self._grant(r, visits, xy, ts, now)
        r.last = grant
        grant = self._resolve(r, grant, xy) or grant
        grant = self._aside(r, grant)
        r.last = grant
        if before != (r.holds, r.waiting, r.wait_for):
            self.version += 1
        return grant

    def release(self, robot: str) -> bool:
        """Drop everything ``robot`` holds and its places in the queues (False: unknown)."""
        r = self.robots.pop(robot, None)
        if r is None:
            return False
        self._set_holds(r, {})
        self._dequeue(r, ())
        self.version += 1
        return True

    def expire(self, now: float) -> list[str]:
        """Release every robot whose lease ran out by ``now``; their names."""
        gone = sorted(n for n, r in self.robots.items() if r.expires <= now)
        for n in gone:
            self.release(n)
        return gone

    def waits(self) -> dict[str, str]:
        """The wait-for graph: each waiting robot and the robot it waits for."""
        return {n: r.wait_for for n, r in self.robots.items() if r.wait_for}

    def holds(self, robot: str) -> tuple[int, ...]:
        r = self.robots.get(robot)
        return tuple(sorted(r.holds)) if r else ()

    # ------------------------------------------------------------------ the route

    def _check(self, robot: str, route: Sequence[RoutePoint], lease: float) -> None:
        if not robot:
            raise TrafficError("a route needs the robot's name")
        if not route:
            raise TrafficError(f"robot {robot!r} sent an empty route (its first point is "
                               "where it is)")
        if len(route) > self.max_route:
            raise TrafficError(f"route of {len(route)} points; at most {self.max_route} "
                               "(send one point every 0.25 m or so)")
        for i, p in enumerate(route):
            if not (math.isfinite(p.x) and math.isfinite(p.y) and math.isfinite(p.t)):
                raise TrafficError(f"route point {i} is not finite: ({p.x}, {p.y}, t={p.t})")
        if not (math.isfinite(lease) and 0 < lease <= self.max_lease):
            raise TrafficError(f"lease must be in (0, {self.max_lease}] s, got {lease}")

    def _visits(self, xy: np.ndarray) -> list[_Visit]:
        """The route's segments in order (points off the free space belong to the segment
        before them)."""
        seg = self.map.segments_at(xy)
        d = np.hypot(*np.diff(xy, axis=0).T) if len(xy) > 1 else np.zeros(0)
        s = np.concatenate(([0.0], np.cumsum(d)))
        out: list[_Visit] = []
        cur, first = -1, 0
        for i, sid in enumerate(seg.tolist()):
            if sid < 0 or sid == cur:
                continue
            if cur >= 0:
                out.append(_Visit(cur, first, i - 1, float(s[first]), float(s[i - 1])))
            cur, first = sid, i
        if cur >= 0:
            out.append(_Visit(cur, first, len(seg) - 1, float(s[first]), float(s[-1])))
        return out

    def _narrow(self, sid: int) -> bool:
        return self.map.segments[sid].narrow

    def _chain(self, visits: list[_Visit], k: int) -> tuple[list[_Visit], int]:
        """The narrow visits from ``visits[k]`` up to the next passing place, and the index
        of the visit after them."""
        chain = [visits[k]]
        j = k + 1
        while j < len(visits):
            wide_from = j
            while j < len(visits) and not self._narrow(visits[j].segment):
                j += 1
            if j == len(visits):
                return chain, wide_from
            gap = visits[j].s_first - visits[wide_from].s_first
            if gap >= self.passing_length:
                return chain, wide_from
            chain.extend(v for v in visits[wide_from:j + 1] if self._narrow(v.segment))
            j += 1
        return chain, j

    def _free_for(self, r: _Robot, sid: int) -> str:
        """'' when ``r`` may have narrow segment ``sid``; else the robot it must wait for."""
        others = self.holders.get(sid, set()) - {r.name}
        if others:
            return min(others, key=self._priority)
        if sid in r.holds:
            return ""
        queue = self.queues.get(sid, [])
        for _, name in queue:
            if name == r.name:
                return ""
            if name in self.robots:
                return name
        return ""

    def _grant(self, r: _Robot, visits: list[_Visit], xy: np.ndarray, ts: np.ndarray,
               now: float) -> Grant:
        n = len(xy)
        held: dict[int, Hold] = {}
        r.inside = visits[0].segment if visits and self._narrow(visits[0].segment) else -1
        stop_index, stop, wait_for = n, None, ""
        blocked: tuple[int, ...] = ()
        k = 0
        while k < len(visits):
            v = visits[k]
            if not self._narrow(v.segment):
                k += 1
                continue
            if k > 0 and ts[v.first] > self.horizon:
                stop_index, stop = self._stop_before(xy, v.first, v.s_first)
                break
            chain, nxt = self._chain(visits, k)
            inside = k == 0  # the robot stands in chain[0]: it holds it whoever else does
            ahead = chain[1:] if inside else chain
            refused = [c for c in ahead if self._free_for(r, c.segment)]
            if refused:
                wait_for = self._free_for(r, refused[0].segment)
                blocked = tuple(c.segment for c in ahead)
                stop_index, stop = self._stop_before(xy, refused[0].first, refused[0].s_first)
                if inside:
                    held[v.segment] = self._hold(v, ts, now)
                break
            for c in chain:
                held[c.segment] = self._hold(c, ts, now)
            k = nxt
        self._set_holds(r, held)
        self._dequeue(r, blocked)
        for sid in blocked:
            q = self.queues.setdefault(sid, [])
            if all(name != r.name for _, name in q):
                q.append((now, r.name))
                q.sort(key=lambda e: (e[0], *self._priority(e[1])))
        r.waiting, r.wait_for = blocked, wait_for
        r.route_cells = self._cells(xy)
        return Grant(r.name, stop is None and stop_index == n, stop_index, stop, wait_for,
                     tuple(held[s] for s in sorted(held)), r.expires)

    def _cells(self, xy: np.ndarray) -> frozenset[tuple[int, int]]:
        """The coarse cells a route passes through."""
        px = self.map.grid.resolution * self.map.k
        ox, oy, _ = self.map.grid.origin
        rc = np.floor((xy[:, ::-1] - (oy, ox)) / px).astype(np.int64)
        return frozenset(map(tuple, np.unique(rc, axis=0).tolist()))

    def _hold(self, v: _Visit, ts: np.ndarray, now: float) -> Hold:
        return Hold(v.segment, now + float(ts[v.first]), now + float(ts[v.last]))

    def _stop_before(self, xy: np.ndarray, index: int, s_at: float
                     ) -> tuple[int, tuple[float, float]]:
        """The route index ``stand_off`` metres of route before ``index`` (not before the
        start) and its point."""
        d = np.hypot(*np.diff(xy[:index + 1], axis=0).T) if index > 0 else np.zeros(0)
        s = np.concatenate(([0.0], np.cumsum(d)))
        target = max(0.0, s[-1] - self.stand_off)
        i = int(np.searchsorted(s, target, side="right")) - 1
        i = max(0, min(i, index))
        return i, (float(xy[i, 0]), float(xy[i, 1]))

    def _set_holds(self, r: _Robot, held: dict[int, Hold]) -> None:
        for sid in set(r.holds) - set(held):
            hs = self.holders.get(sid)
            if hs is not None:
                hs.discard(r.name)
                if not hs:
                    del self.holders[sid]
        for sid in held:
            self.holders.setdefault(sid, set()).add(r.name)
        r.holds = held

    def _dequeue(self, r: _Robot, keep: Sequence[int]) -> None:
        for sid in list(self.queues):
            if sid in keep:
                continue
            q = [e for e in self.queues[sid] if e[1] != r.name]
            if q:
                self.queues[sid] = q
            else:
                del self.queues[sid]

    # ------------------------------------------------------------------ deadlocks

    def _priority(self, name: str) -> tuple[float, str]:
        return self.robots[name].since, name

    def _cycle_from(self, start: str) -> list[str]:
        """The cycle of waiters ``start`` is on (empty when none)."""
        seen: list[str] = []
        cur = start
        while cur and cur in self.robots and cur not in seen:
            seen.append(cur)
            cur = self.robots[cur].wait_for
        if cur in seen:
            return seen[seen.index(cur):]
        return []

    def _resolve(self, r: _Robot, grant: Grant, xy: np.ndarray) -> Grant | None:
        """If ``r`` is on a cycle of waiters or shares a narrow segment, make the robot of
        lowest priority among them yield; the new grant when that is ``r``."""
        group = self._cycle_from(r.name)
        if not group and r.inside >= 0 and len(self.holders.get(r.inside, ())) > 1:
            group = sorted(self.holders[r.inside])
        if not group:
            return None
        victim = max(group, key=self._priority)
        v = self.robots[victim]
        place = self._passing_place(v, group)
        self._set_holds(v, {})
        self._dequeue(v, ())
        v.wait_for, v.waiting = "", ()
        self.version += 1
        yielded = Grant(victim, False, 0, place, next(n for n in group if n != victim), (),
                        v.expires, must_yield=True, yield_to=place)
        v.last = yielded
        return yielded if victim == r.name else None

    def _aside(self, r: _Robot, grant: Grant) -> Grant:
        """A wait whose robot stands or would stop where the robot it waits for drives (its
        route's cells and their neighbours): the same wait at a clear wide cell off that
        route and every other robot's, if there is one within 3 m."""
        other = self.robots.get(grant.wait_for)
        if grant.granted or grant.must_yield or grant.stop is None or other is None:
            return grant
        lane = _dilate(other.route_cells)
        m = self.map
        if m.cell_at(*grant.stop) not in lane and m.cell_at(*r.position) not in lane:
            return grant
        place = self._passing_place(r, tuple(self.robots), clear=True)  # off every route
        if place is None or math.dist(place, r.position) > 3.0:
            return grant
        return replace(grant, yield_to=place, step_aside=True)

    def _passing_place(self, v: _Robot, group: Sequence[str], *, clear: bool = False
                       ) -> tuple[float, float] | None:
        """The centre of the nearest wide cell to ``v``, through free cells, that no other
        robot of ``group`` drives through or beside (None: there is none); with ``clear``,
        a cell with no wall in it."""
        m = self.map
        avoid = _dilate(frozenset().union(*(self.robots[n].route_cells for n in group
                                            if n != v.name)))
        start = m.cell_at(*v.position)
        if not (0 <= start[0] < m.rows and 0 <= start[1] < m.cols):
            return None
        seen = {start}
        todo = deque([start])
        while todo:
            cell = todo.popleft()
            sid = int(m.segment_of[cell])
            if (sid >= 0 and not m.segments[sid].narrow and cell not in avoid
                    and (not clear or m.clear_cells[cell])):
                return m.cell_centre(cell)
            r0, c0 = cell
            for nb in ((r0 + 1, c0), (r0 - 1, c0), (r0, c0 + 1), (r0, c0 - 1)):
                if (0 <= nb[0] < m.rows and 0 <= nb[1] < m.cols and nb not in seen
                        and m.free_cells[nb]):
                    seen.add(nb)
                    todo.append(nb)
        return None

    def grant_of(self, robot: str) -> Grant | None:
        """The last answer given to ``robot`` (None: unknown)."""
        r = self.robots.get(robot)
        return r.last if r else None


def _dilate(cells: frozenset[tuple[int, int]]) -> set[tuple[int, int]]:
    """``cells`` and their eight neighbours."""
    return {(r + dr, c + dc) for r, c in cells for dr in (-1, 0, 1) for dc in (-1, 0, 1)}
