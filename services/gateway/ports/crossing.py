"""`check_route`: whether a goal on another map is reachable through nav's point connections
(docs/robot-api.md §6.7), asked before a task is made."""

from __future__ import annotations

from zenros.building import elevator_of_path
from zenros.maps.maproute import Hop, NoRoute, find_route, links_of
from zenros.msgs import zenros_msgs as zm

from ..errors import Conflict, NotFound
from .nav_services import NavServices

__all__ = ["check_route"]


async def check_route(link: NavServices, current: str, target: str) -> None:
    """Refuse (409) a goal on map ``target`` that no route of direct connections reaches
    from map ``current``, before a task is made (the task checks again when it runs)."""
    names, _ = await link.maps()
    if names and target not in names:
        raise NotFound(f"unknown map {target!r}; known maps: {', '.join(names)}")
    res = await link.call(zm.ListPointConnections, zm.ListPointConnectionsRequest())
    try:
        route = find_route(links_of(res.points, res.connections), current, target)
    except NoRoute as exc:
        raise Conflict(f"{exc}: POST /navigation/point_connections links maps") from exc
    for hop in route:
        why = "" if hop.type == "direct" else _unrideable(link, hop)
        if why:
            raise Conflict(f"the route from map {current!r} to map {target!r} needs the "
                           f"{hop.describe()}: {why}")


def _unrideable(link: NavServices, hop: Hop) -> str:
    """Why an elevator connection cannot be ridden now ("" when its controller runs)."""
    if hop.type != "elevator":
        return f"unknown connection type {hop.type!r}"
    name = elevator_of_path(hop.leave.path)
    if name is None or elevator_of_path(hop.enter.path) != name:
        return (f"its points are not the hall points of one elevator (paths "
                f"{hop.leave.path!r}, {hop.enter.path!r}; docs/building.md)")
    if not link.node.graph.servers(f"/building/elevators/{name}/command"):
        return (f"no elevator controller serves elevator {name!r} (launch with "
                "building:=PATH; docs/building.md)")
    return ""
