"""Map routes: the point connections that take the robot from one map to another (docs/robot-api.md
§6.7).

The maps are the graph's nodes and each available connection between nav points of two
different maps is an edge, usable both ways. `find_route` runs Dijkstra with the cost
(elevator rides, connections): a route without an elevator is preferred to one with
fewer connections but a ride; among equals the first stored connection wins, so the
answer is deterministic. Shared by the tasks service (which drives a route) and the
gateway (which refuses a goal no route reaches).
"""

from __future__ import annotations

import heapq
from collections.abc import Iterable
from typing import Any, NamedTuple

__all__ = ["Hop", "Link", "NoRoute", "PointEnd", "find_route", "links_of"]


class PointEnd(NamedTuple):
    """One nav point: map, path, the point's index in the path (not named ``index``: that
    would shadow ``tuple.index``)."""

    map: str
    path: str
    point_index: int

    def label(self) -> str:
        return f"{self.map}/{self.path}[{self.point_index}]"


class Link(NamedTuple):
    """A stored connection as the planner sees it."""

    id: str
    type: str  # "direct" or "elevator"
    available: bool
    a: PointEnd
    b: PointEnd


class Hop(NamedTuple):
    """Go to ``leave`` on the current map, then carry on from ``enter`` on the next."""

    id: str
    type: str
    leave: PointEnd
    enter: PointEnd

    def describe(self) -> str:
        return f"{self.type} connection {self.id} ({self.leave.label()} -> " \
               f"{self.enter.label()})"


def links_of(points: Iterable[Any], connections: Iterable[Any]) -> list[Link]:
    """`Link`s from nav's ``list_point_connections`` answer (its ``points`` and
    ``connections``): a connection whose point no longer exists is unavailable."""
    known = {(p.map_name, p.path_name, p.index) for p in points}
    out = []
    for c in connections:
        if len(c.points) != 2:
            continue
        a, b = (PointEnd(p.map_name, p.path_name, p.index) for p in c.points)
        out.append(Link(c.id, c.type, bool(c.is_available) and a in known and b in known,
                        a, b))
    return out


class NoRoute(LookupError):
    """No chain of available connections joins the two maps."""


def find_route(links: Iterable[Link], start: str, goal: str) -> list[Hop]:
    """The hops from map ``start`` to map ``goal`` (empty when they are the same map).

    Raises:
        NoRoute: no available connections join them (the message says what was known).
    """
    if start == goal:
        return []
    edges: dict[str, list[Hop]] = {}
    skipped = 0
    for link in links:
        if link.a.map == link.b.map:
            continue  # joins two paths of one map: no map change
        if not link.available:
            skipped += 1
            continue
        edges.setdefault(link.a.map, []).append(Hop(link.id, link.type, link.a, link.b))
        edges.setdefault(link.b.map, []).append(Hop(link.id, link.type, link.b, link.a))
    best: dict[str, tuple[int, int]] = {start: (0, 0)}
    via: dict[str, Hop] = {}
    queue: list[tuple[int, int, int, str]] = [(0, 0, 0, start)]
    order = 0
    while queue:
        rides, hops, _, here = heapq.heappop(queue)
        if (rides, hops) > best.get(here, (rides, hops)):
            continue
        if here == goal:
            break
        for hop in edges.get(here, []):
            cost = (rides + (hop.type == "elevator"), hops + 1)
            there = hop.enter.map
            if there not in best or cost < best[there]:
                best[there] = cost
                via[there] = hop
                order += 1
                heapq.heappush(queue, (*cost, order, there))
    if goal not in via:
        note = f" ({skipped} unavailable connection(s) skipped)" if skipped else ""
        raise NoRoute(f"no route from map {start!r} to map {goal!r} through the point "
                      f"connections{note}")
    route: list[Hop] = []
    here = goal
    while here != start:
        hop = via[here]
        route.append(hop)
        here = hop.leave.map
    return route[::-1]
