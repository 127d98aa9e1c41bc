"""REST ``/navigation/point_connections`` (docs/robot-api.md §6.7): links between nav points of
different maps, kept by the nav service (``list/add/delete_point_connection``)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

import msgspec
from zenros.msgs import zenros_msgs as zm

from ..api import Answer, Api, Call
from ..context import Context
from ..fields import Name

__all__ = ["add_connection_routes"]

Index = Annotated[int, msgspec.Meta(ge=0, le=10000)]


class PointIn(msgspec.Struct, forbid_unknown_fields=True):
    """One end: ``map``, ``path``, ``index``; a listed point's ``type``/``levels`` (echoed
    back by clients that copy points from GET) are accepted and not used."""

    map: Name
    path: Name
    index: Index
    type: str = ""
    levels: list[int] = msgspec.field(default_factory=list)
    level: int = 0


class ConnectionBody(msgspec.Struct, forbid_unknown_fields=True):
    points: Annotated[list[PointIn], msgspec.Meta(min_length=2, max_length=2)]
    type: Literal["direct", "elevator"]
    is_available: bool = True


class IdQuery(msgspec.Struct, forbid_unknown_fields=True):
    id: Annotated[str, msgspec.Meta(min_length=1, max_length=64)]


async def floors(ctx: Context) -> dict[str, tuple[str, list[int]]]:
    link = ctx.nav_services
    res = await link.call(zm.ListMaps, zm.ListMapsRequest())
    return {m.name: (m.type or "floor", list(m.levels)) for m in res.maps}


def ref(p: Any, kinds: dict[str, tuple[str, list[int]]]) -> dict[str, Any]:
    kind, levels = kinds.get(p.map_name, ("floor", []))
    return {"map": p.map_name, "path": p.path_name, "index": p.index, "type": kind,
            "levels": levels}


def connection(c: Any, kinds: dict[str, tuple[str, list[int]]]) -> dict[str, Any]:
    return {"_id": {"$oid": c.oid}, "points": [ref(p, kinds) for p in c.points],
            "type": c.type, "is_available": c.is_available, "id": c.id}


async def get_connections(call: Call[None, None]) -> Answer:
    """Every nav point of every map (``points``) and every connection
    (``connections``)."""
    link = call.ctx.nav_services
    res = await link.call(zm.ListPointConnections, zm.ListPointConnectionsRequest())
    kinds = await floors(call.ctx)
    points = [{"x": p.x, "y": p.y, "theta": p.theta, "name": p.name, **ref(p, kinds)}
              for p in res.points]
    return {"points": points,
            "connections": [connection(c, kinds) for c in res.connections]}


async def post_connection(call: Call[ConnectionBody, None]) -> Answer:
    """Connect two existing nav points, ``direct`` (the same spot in two maps) or via
    an ``elevator``; returns the connection with its ``id``."""
    link = call.ctx.nav_services
    b = call.body
    res = await link.call(zm.AddPointConnection, zm.AddPointConnectionRequest(
        points=[zm.PointRef(map_name=p.map, path_name=p.path, index=p.index)
                for p in b.points], type=b.type, is_available=b.is_available))
    return connection(res.connection, await floors(call.ctx))


async def delete_connection(call: Call[None, IdQuery]) -> Answer:
    """Delete the connection ``id``."""
    link = call.ctx.nav_services
    await link.call(zm.DeletePointConnection,
                    zm.DeletePointConnectionRequest(id=call.query.id))
    return {"status": "ok"}


def add_connection_routes(api: Api) -> None:
    """Route the point-connection operations."""
    api.add("GET", "/navigation/point_connections", get_connections)
    api.add("POST", "/navigation/point_connections", post_connection)
    api.add("DELETE", "/navigation/point_connections", delete_connection)
