"""REST ``/navigation/...`` lifecycle, queries, maps and the initial pose (docs/robot-api.md
§6.1-§6.3, §6.9); goals and charging are in `rest_goals`."""

from __future__ import annotations

import asyncio
from typing import Annotated, Any

import msgspec
from starlette.responses import Response
from zenros.msgs import zenros_msgs as zm

from ...state.core import NavUnavailable
from ..api import Answer, Api, ApiError, Call
from ..context import Context
from ..fields import Angle, Coord, Name, OptName
from ..map_image import grid_pgm, grid_png
from .mapping import refuse_while_mapping

__all__ = ["add_nav_routes"]


class StartQuery(msgspec.Struct, forbid_unknown_fields=True):
    map: OptName = ""
    path: OptName = ""
    start_index: Annotated[int, msgspec.Meta(ge=-1, le=10000)] = -1
    level: int = 0


class ReloadQuery(msgspec.Struct, forbid_unknown_fields=True):
    map: Name
    path: OptName = ""


class NamedMap(msgspec.Struct, forbid_unknown_fields=True):
    name: OptName = ""


class TrackQuery(msgspec.Struct, forbid_unknown_fields=True):
    map_name: OptName = ""


class SavedMapsQuery(msgspec.Struct, forbid_unknown_fields=True):
    name: OptName = ""
    type: OptName = ""


class SwitchQuery(msgspec.Struct, forbid_unknown_fields=True):
    map_name: Name


class InitPose(msgspec.Struct, forbid_unknown_fields=True):
    """x, y (m) and z: the heading (yaw, rad), as §6.9 names it."""

    x: Coord
    y: Coord
    z: Angle = 0.0


async def start(call: Call[None, StartQuery]) -> Answer:
    """Start navigation (optionally on ``map``/``path``, relocalised at ``start_index``)."""
    core = call.ctx.core
    nav = call.ctx.nav_actions
    link = call.ctx.nav_services
    current_map = call.ctx.nav_services.current_map
    point = call.ctx.nav_actions.point
    publish_initialpose = call.ctx.nav_services.publish_initialpose
    q = call.query
    if not nav.available():
        raise core.presence.error("nav", "navigation is not available")
    refuse_while_mapping(call.ctx, "start navigation")
    core.state.busy = True  # §7: Busy while the map loads and the robot relocalises
    try:
        if q.map and q.map != await current_map():
            res = await link.call(zm.SwitchMap, zm.SwitchMapRequest(map_name=q.map))
            if not res.success:
                raise ApiError(400, res.message)
        if q.path:
            nav.path_name = q.path
        if q.start_index >= 0:
            x, y, th = await point(q.start_index)
            publish_initialpose(x, y, th)
    finally:
        core.state.busy = False
    nav.open()
    return {"result": True, "description": "navigation started"}


async def reload(call: Call[None, ReloadQuery]) -> Answer:
    """Load ``map`` (when not loaded) and make ``path`` the current path."""
    nav, link = call.ctx.nav_actions, call.ctx.nav_services
    current_map = link.current_map
    q = call.query
    if q.map != await current_map():
        res = await link.call(zm.SwitchMap, zm.SwitchMapRequest(map_name=q.map))
        if not res.success:
            raise ApiError(400, res.message)
    if q.path:
        nav.path_name = q.path
    return {"status": "ok", "map": q.map, "path": q.path}


async def stop(call: Call[None, None]) -> Answer:
    """Stop navigation: cancel the goal; navStatus goes to 0."""
    core, nav = call.ctx.core, call.ctx.nav_actions
    try:
        await nav.stop()
    except NavUnavailable as exc:
        raise core.presence.error("nav", str(exc)) from exc
    return {"result": True, "description": "navigation stopped"}


async def pose(call: Call[None, None]) -> Answer:
    """Robot pose in ``map``: ``x``, ``y`` (m), ``angle`` (rad); -1 while unknown."""
    core = call.ctx.core
    st = core.status
    return {"x": st.currentPosX, "y": st.currentPosY, "angle": st.currentAngle}


async def current_path(call: Call[None, None]) -> Answer:
    """The loaded ``map`` and ``path``."""
    core, nav, current_map = call.ctx.core, call.ctx.nav_actions, call.ctx.nav_services.current_map
    try:
        path = await nav.current_path()
    except NavUnavailable as exc:
        raise core.presence.error("nav", str(exc)) from exc
    except ValueError:
        path = ""
    return {"map": await current_map(), "path": path}


async def target_distance(call: Call[None, None]) -> Answer:
    """Distance (m) to the current goal; -1 without one."""
    core = call.ctx.core
    return {"distance": core.status.targetDistance}


def map_object(m: Any) -> dict[str, Any]:
    return {"name": m.name, "resolution": m.resolution, "origin": list(m.origin),
            "occupied_thresh": m.occupied_thresh, "free_thresh": m.free_thresh,
            "negate": m.negate, "md5sum": m.md5sum, "type": m.type,
            "levels": list(m.levels), "slam_type": m.slam_type}


async def saved_maps(call: Call[None, SavedMapsQuery]) -> Answer:
    """The stored maps (§6.3 map objects), optionally one ``name`` or one slam ``type``."""
    link = call.ctx.nav_services
    q = call.query
    res = await link.call(zm.ListMaps, zm.ListMapsRequest(name=q.name))
    return [map_object(m) for m in res.maps if not q.type or m.slam_type == q.type]


async def get_current_map(call: Call[None, None]) -> Answer:
    """The map in use: ``name`` and ``md5sum``."""
    link = call.ctx.nav_services
    res = await link.call(zm.GetCurrentMap, zm.GetCurrentMapRequest())
    return {"name": res.name, "md5sum": res.md5sum}


GRID_WAIT = 3.0  # s a request waits for the grid of a map nav has just loaded


async def loaded_grid(ctx: Context, name: str) -> Any:
    """The loaded map's grid; ``name`` must be it (or empty). Right after a switch, nav names
    the new map before its grid (latched ``map``) has reached the gateway: the grid whose
    size, resolution and origin are the loaded map's is waited for, `GRID_WAIT` s at most."""
    core, link = ctx.core, ctx.nav_services
    loaded = await link.call(zm.GetCurrentMap, zm.GetCurrentMapRequest())
    current = loaded.name
    if name and name != current:
        listed = await link.call(zm.ListMaps, zm.ListMapsRequest(name=name))
        if not listed.maps:
            raise ApiError(404, f"unknown map {name!r}")
        raise ApiError(409, f"map {name!r} is stored but not loaded; the gateway renders "
                            f"the loaded map ({current!r}): switch_map first")
    loop = asyncio.get_running_loop()
    deadline = loop.time() + GRID_WAIT
    while not _is_grid_of(link.grid, loaded.info) and loop.time() < deadline:
        await asyncio.sleep(GRID_POLL)
    if link.grid is None:
        raise core.presence.error("nav", "no map received from the nav service yet")
    if not _is_grid_of(link.grid, loaded.info):
        raise core.presence.error("nav", f"the grid of map {current!r} has not reached the "
                                         f"gateway within {GRID_WAIT:g} s")
    return link.grid


GRID_POLL = 0.02  # s between looks at the grid while waiting for it


def _is_grid_of(grid: Any, info: zm.MapInfo) -> bool:
    """Whether ``grid`` (an OccupancyGrid or None) has the stored map's size, resolution and
    origin (a map nav did not describe, width 0, takes any grid)."""
    if grid is None:
        return False
    if info.width <= 0:
        return True
    g, origin = grid.info, grid.info.origin.position
    return bool(g.width == info.width and g.height == info.height
                and abs(g.resolution - info.resolution) < 1e-9
                and abs(origin.x - info.origin[0]) < 1e-6
                and abs(origin.y - info.origin[1]) < 1e-6)


async def map_png(call: Call[None, NamedMap]) -> Answer:
    """The current map as a PNG image (``name`` must be the current map or empty)."""
    return Response(grid_png(await loaded_grid(call.ctx, call.query.name)), media_type="image/png")


async def map_pgm(call: Call[None, NamedMap]) -> Answer:
    """The current map as a PGM image (``name`` must be the current map or empty)."""
    return Response(grid_pgm(await loaded_grid(call.ctx, call.query.name)),
                    media_type="image/x-portable-graymap")


async def robot_tracks(call: Call[None, TrackQuery]) -> Answer:
    """Where the robot has been on ``map_name`` (default: the current map), one
    ``{x, y, z}`` a second, the last hour, since the gateway started."""
    nav, current_map = call.ctx.nav_actions, call.ctx.nav_services.current_map
    name = call.query.map_name or await current_map()
    return {"map_name": name,
            "track": [{"x": x, "y": y, "z": 0.0} for x, y in nav.tracks.get(name, ())]}


async def switch_map(call: Call[None, SwitchQuery]) -> Answer:
    """Load another stored map."""
    link = call.ctx.nav_services
    res = await link.call(zm.SwitchMap, zm.SwitchMapRequest(map_name=call.query.map_name))
    if not res.success:
        raise ApiError(400, res.message)
    return {"status": "ok"}


async def init_pose(call: Call[InitPose, None]) -> Answer:
    """Set the robot's pose for relocalisation (``z`` is the heading)."""
    publish_initialpose = call.ctx.nav_services.publish_initialpose
    b = call.body
    publish_initialpose(b.x, b.y, b.z)
    return {"status": "ok"}


def add_nav_routes(api: Api) -> None:
    """Route the navigation lifecycle, query and map operations."""
    result = {"result_style": True}
    api.add("GET", "/navigation/start", start, **result)
    api.add("GET", "/navigation/stop", stop, **result)
    api.add("GET", "/navigation/reload", reload)
    api.add("GET", "/navigation/pose", pose)
    api.add("GET", "/navigation/current_path", current_path)
    api.add("GET", "/navigation/target_distance", target_distance)
    api.add("GET", "/navigation/saved_maps", saved_maps)
    api.add("GET", "/navigation/current_map", get_current_map)
    api.add("GET", "/navigation/map_png", map_png, media_type="image/png")
    api.add("GET", "/navigation/map_pgm", map_pgm,
            media_type="image/x-portable-graymap")
    api.add("GET", "/navigation/robot_tracks", robot_tracks)
    api.add("GET", "/navigation/switch_map", switch_map)
    api.add("POST", "/navigation/init_pose", init_pose)
