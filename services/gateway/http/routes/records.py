"""REST ``/navigation/path``, ``nav_points``, ``virtual_wall``, ``skip_area`` (docs/robot-api.md
§6.6, §6.8) and ``landmarks`` (§6.12), on the nav service's path, nav-point, wall, keep-out
and landmark services."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, TypeVar

import msgspec
from zenros.msgs import zenros_msgs as zm

from ..api import Answer, Api, ApiError, Call
from ..context import Context
from ..fields import Name, OptName
from ..path_data import (
    format_areas,
    format_nav_points,
    format_points,
    format_walls,
    parse_areas,
    parse_nav_points,
    parse_points,
    parse_walls,
)

__all__ = ["add_record_routes"]

T = TypeVar("T")

Text = Annotated[str, msgspec.Meta(max_length=1_000_000)]


class ListQuery(msgspec.Struct, forbid_unknown_fields=True):
    map_name: OptName = ""
    path_name: OptName = ""


class PathRefQuery(msgspec.Struct, forbid_unknown_fields=True):
    map_name: Name
    path_name: Name


class PathBody(msgspec.Struct, forbid_unknown_fields=True):
    map_name: Name
    path_name: Name
    path_data: Text


class WallBody(msgspec.Struct, forbid_unknown_fields=True):
    map_name: Name
    virtual_wall: Text
    path_name: OptName = ""


class AreaBody(msgspec.Struct, forbid_unknown_fields=True):
    map_name: Name
    skip_area: Text
    path_name: OptName = ""


class MapRefQuery(msgspec.Struct, forbid_unknown_fields=True):
    map_name: Name
    path_name: OptName = ""


class LandmarkQuery(msgspec.Struct, forbid_unknown_fields=True):
    map_name: OptName = ""


def _parsed(fn: Callable[[str], T], text: str) -> T:
    try:
        return fn(text)
    except ValueError as exc:
        raise ApiError(400, str(exc)) from exc


async def listing(ctx: Context, q: ListQuery) -> list[str] | dict[str, list[str]]:
    link = ctx.nav_services
    res = await link.call(zm.ListPaths, zm.ListPathsRequest(map_name=q.map_name))
    if q.map_name:
        return [p.path_name for p in res.paths]
    out: dict[str, list[str]] = {}
    for p in res.paths:
        out.setdefault(p.map_name, []).append(p.path_name)
    return out


async def get_path(call: Call[None, ListQuery]) -> Answer:
    """A path's points (``path_data`` lines ``x y z``), or the path names (§6.6)."""
    link = call.ctx.nav_services
    q = call.query
    if not (q.map_name and q.path_name):
        return await listing(call.ctx, q)
    res = await link.call(zm.GetPath, zm.GetPathRequest(map_name=q.map_name,
                                                       path_name=q.path_name))
    return {"map_name": res.map_name, "path_name": res.path_name,
            "path_data": format_points(res.points)}


async def set_path(call: Call[PathBody, None]) -> Answer:
    """Create or replace a path's points."""
    link = call.ctx.nav_services
    b = call.body
    points = _parsed(parse_points, b.path_data)
    res = await link.call(zm.SetPath, zm.SetPathRequest(
        map_name=b.map_name, path_name=b.path_name, points=points))
    return {"map_name": res.map_name, "path_name": res.path_name,
            "path_data": format_points(res.points)}


async def delete_path(call: Call[None, PathRefQuery]) -> Answer:
    """Delete a path and its nav points."""
    link = call.ctx.nav_services
    q = call.query
    await link.call(zm.DeletePath, zm.DeletePathRequest(map_name=q.map_name,
                                                       path_name=q.path_name))
    return {"status": "ok"}


async def get_points(call: Call[None, ListQuery]) -> Answer:
    """A path's nav points (lines ``x y z theta errorX errorY direction [name]``)."""
    link = call.ctx.nav_services
    q = call.query
    if not (q.map_name and q.path_name):
        return await listing(call.ctx, q)
    res = await link.call(zm.GetNavPoints, zm.GetNavPointsRequest(
        map_name=q.map_name, path_name=q.path_name))
    return {"map_name": res.map_name, "path_name": res.path_name,
            "path_data": format_nav_points(res.points)}


async def set_points(call: Call[PathBody, None]) -> Answer:
    """Create or replace a path's nav points."""
    link = call.ctx.nav_services
    b = call.body
    points = _parsed(parse_nav_points, b.path_data)
    res = await link.call(zm.SetNavPoints, zm.SetNavPointsRequest(
        map_name=b.map_name, path_name=b.path_name, points=points))
    return {"map_name": res.map_name, "path_name": res.path_name,
            "path_data": format_nav_points(res.points)}


async def delete_points(call: Call[None, PathRefQuery]) -> Answer:
    """Delete a path's nav points."""
    link = call.ctx.nav_services
    q = call.query
    await link.call(zm.DeleteNavPoints, zm.DeleteNavPointsRequest(
        map_name=q.map_name, path_name=q.path_name))
    return {"status": "ok"}


async def get_walls(call: Call[None, MapRefQuery]) -> Answer:
    """The map's virtual walls (``x y`` per line; an empty line between walls)."""
    link = call.ctx.nav_services
    q = call.query
    res = await link.call(zm.GetVirtualWalls,
                          zm.GetVirtualWallsRequest(map_name=q.map_name))
    return {"map_name": q.map_name, "path_name": q.path_name,
            "virtual_wall": format_walls(res.walls)}


async def set_walls(call: Call[WallBody, None]) -> Answer:
    """Replace the map's virtual walls."""
    link = call.ctx.nav_services
    b = call.body
    walls = _parsed(parse_walls, b.virtual_wall)
    await link.call(zm.SetVirtualWalls, zm.SetVirtualWallsRequest(
        map_name=b.map_name, walls=walls))
    return {"map_name": b.map_name, "path_name": b.path_name,
            "virtual_wall": format_walls(walls)}


async def delete_walls(call: Call[None, MapRefQuery]) -> Answer:
    """Remove the map's virtual walls."""
    link = call.ctx.nav_services
    q = call.query
    await link.call(zm.SetVirtualWalls, zm.SetVirtualWallsRequest(map_name=q.map_name))
    return {"status": "ok"}


async def get_areas(call: Call[None, MapRefQuery]) -> Answer:
    """The map's forbidden areas (``x1 y1 x2 y2`` rectangles, one per line)."""
    link = call.ctx.nav_services
    q = call.query
    res = await link.call(zm.GetForbiddenAreas,
                          zm.GetForbiddenAreasRequest(map_name=q.map_name))
    return {"map_name": q.map_name, "path_name": q.path_name,
            "skip_area": format_areas(res.areas)}


async def set_areas(call: Call[AreaBody, None]) -> Answer:
    """Replace the map's forbidden areas."""
    link = call.ctx.nav_services
    b = call.body
    areas = _parsed(parse_areas, b.skip_area)
    await link.call(zm.SetForbiddenAreas, zm.SetForbiddenAreasRequest(
        map_name=b.map_name, areas=areas))
    return {"map_name": b.map_name, "path_name": b.path_name,
            "skip_area": format_areas(areas)}


async def delete_areas(call: Call[None, MapRefQuery]) -> Answer:
    """Remove the map's forbidden areas."""
    link = call.ctx.nav_services
    q = call.query
    await link.call(zm.SetForbiddenAreas,
                    zm.SetForbiddenAreasRequest(map_name=q.map_name))
    return {"status": "ok"}


async def get_landmarks(call: Call[None, LandmarkQuery]) -> Answer:
    """A map's reflectors (the current map's without ``map_name``): ``landmarks``, each
    ``id``, ``x``, ``y``, ``theta`` (0: a reflector has no heading) and ``radius`` (m)."""
    link = call.ctx.nav_services
    res = await link.call(zm.GetLandmarks, zm.GetLandmarksRequest(map_name=call.query.map_name))
    return {"map_name": res.map_name, "landmarks": [
        {"id": m.id, "x": m.x, "y": m.y, "theta": 0.0, "radius": m.radius}
        for m in res.landmarks]}


def add_record_routes(api: Api) -> None:
    """Route the path, nav-point, virtual-wall, skip-area and landmark operations."""
    for method, path, fn, kw in (
        ("GET", "/navigation/path", get_path, {}),
        ("POST", "/navigation/path", set_path, {}),
        ("PUT", "/navigation/path", set_path, {}),
        ("DELETE", "/navigation/path", delete_path, {}),
        ("GET", "/navigation/nav_points", get_points, {}),
        ("POST", "/navigation/nav_points", set_points, {}),
        ("PUT", "/navigation/nav_points", set_points, {}),
        ("DELETE", "/navigation/nav_points", delete_points, {}),
        ("GET", "/navigation/virtual_wall", get_walls, {}),
        ("POST", "/navigation/virtual_wall", set_walls, {}),
        ("DELETE", "/navigation/virtual_wall", delete_walls, {}),
        ("GET", "/navigation/skip_area", get_areas, {}),
        ("POST", "/navigation/skip_area", set_areas, {}),
        ("DELETE", "/navigation/skip_area", delete_areas, {}),
        ("GET", "/navigation/landmarks", get_landmarks, {}),
    ):
        api.add(method, path, fn, **kw)
