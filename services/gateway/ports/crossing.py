"""`check_route`: whether a goal on another map is reachable through nav's point connections
(docs/robot-api.md §6.7), asked before a task is made."""

from __future__ import annotations

from zenros.maps.maproute import NoRoute, find_route, links_of
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
        if hop.type != "direct":
            raise Conflict(f"the route from map {current!r} to map {target!r} needs the "
                           f"{hop.describe()}: the simulated robot has no elevator")
