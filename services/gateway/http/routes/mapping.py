"""REST ``/map/...`` (docs/robot-api.md §5): building a map with the mapping node (``slam``),
by hand or exploring by itself; the §7 state machine Free → Busy → Mapping → Busy → Free.

Every operation needs a mapping node in the graph (else a 503 saying why). Mapping and
navigating to a goal are exclusive: each refuses while the other runs (409, the §1.2 body).
"""

from __future__ import annotations

import time
from typing import Annotated, Any, Literal

import msgspec
from starlette.responses import Response
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.geometry_msgs import Pose2D

from ...ports.slam_link import SlamPort
from ..api import Answer, Api, ApiError, Call
from ..context import Context
from ..fields import Name, OptName
from ..map_image import grid_png

__all__ = ["add_mapping_routes", "driving_reason", "slam_port"]

Level = Annotated[int, msgspec.Meta(ge=-100, le=1000)]


class StartQuery(msgspec.Struct, forbid_unknown_fields=True):
    """``mode``: ``laser`` (driven by hand, the default) or ``explore`` (by itself)."""

    mode: Literal["laser", "explore"] = "laser"


class UpdateQuery(msgspec.Struct, forbid_unknown_fields=True):
    """``map``: the saved map to extend (default: nav's current map); ``start_index``: the
    nav point of ``path`` (default: the map's first path) where the robot stands."""

    map: OptName = ""
    path: OptName = ""
    start_index: Annotated[int, msgspec.Meta(ge=-1, le=10000)] = -1


class TrackQuery(msgspec.Struct, forbid_unknown_fields=True):
    """``keyframes`` true: the pose graph's nodes as last optimised (the spec's second
    variant); false (the default): the poses as they were recorded."""

    keyframes: bool = False


class SaveBody(msgspec.Struct, forbid_unknown_fields=True):
    """``name``: the map's name (letters, digits, ``_ . -``; no path)."""

    name: Name
    type: Literal["floor", "elevator"] = "floor"
    levels: Annotated[list[Level], msgspec.Meta(max_length=200)] = msgspec.field(
        default_factory=list)


def slam_port(ctx: Context) -> SlamPort:
    """The mapping node's port, or the 503 saying why there is none."""
    slam = ctx.slam
    if slam is None:
        raise ApiError(503, "mapping is not available: this gateway has no mapping port")
    if not slam.available():
        raise ctx.core.presence.error("slam", "mapping is not available: no server for "
                                              "slam/start")
    return slam


def driving_reason(ctx: Context) -> str:
    """Why mapping cannot start now ("" if it can): a goal or a loop task is being driven."""
    st = ctx.core.status
    if st.targetStatus in (1, 2):
        what = "navigating to a goal" if st.targetStatus == 1 else "holding a paused goal"
        return (f"the robot is {what} (GalileoStatus targetStatus {st.targetStatus}, "
                f"targetNumID {st.targetNumID}): stop it first (GET /navigation/stop)")
    if st.loopStatus:
        return ("the robot runs a loop task (GalileoStatus loopStatus 1): stop it first "
                "(DELETE /navigation/loop_task)")
    return ""


def refuse_while_mapping(ctx: Context, what: str) -> None:
    """A 409 (§1.2 body) when the robot is building a map (not extending the map in use
    while navigating: ``PUT /navigation/update_map``): ``what`` ("start navigation", "go
    to a nav point", ...) needs the saved map, its nav points and its charge pose."""
    if ctx.core.state.mapping and not (ctx.slam and ctx.slam.update_map):
        raise ApiError(409, f"cannot {what}: the robot is mapping (GalileoStatus mapStatus "
                            "1): save the map (POST /map/current_map_image), then GET "
                            "/map/stop")


def _mapping_reason(slam: SlamPort) -> str:
    st = slam.state()
    if st.state in ("starting", "mapping"):
        what = f"extending map {st.map_name!r}" if st.map_name else "building a new map"
        return f"the robot is mapping already ({what}, mode {st.mode or 'laser'})"
    return ""


def _refuse_while_busy(ctx: Context, slam: SlamPort) -> None:
    reason = _mapping_reason(slam) or driving_reason(ctx)
    if reason:
        raise ApiError(409, f"cannot start mapping: {reason}")


async def _open(ctx: Context, slam: SlamPort, mode: str, map_name: str = "",
                initial_pose: Pose2D | None = None) -> None:
    """Free → Busy → Mapping: start the mapping node, navigation off while it maps."""
    _refuse_while_busy(ctx, slam)
    core = ctx.core
    core.state.busy = True
    try:
        await slam.start(mode, map_name, initial_pose)
        ctx.nav_actions.stopped = True   # §7: mapping and navigation are exclusive
        core.state.nav_open = False
        core.state.mapping = True
        if mode == "explore":
            try:
                await slam.start_explore()
            except Exception:
                await slam.stop()
                core.state.mapping = False
                raise
    finally:
        core.state.busy = False


async def start_mapping(ctx: Context, mode: str) -> None:
    """Start a new map in ``mode`` (``laser`` or ``explore``); ApiError when it cannot."""
    slam = slam_port(ctx)
    if mode == "explore" and not slam.explore_available():
        raise ctx.core.presence.error("explore", "exploring is not available: no server "
                                                 "for the explore action")
    await _open(ctx, slam, mode)


async def start(call: Call[None, StartQuery]) -> Answer:
    """Start a new map: ``mode=laser`` (drive it by hand) or ``explore`` (the robot maps by
    itself, nearest frontier first, and comes back to where it started)."""
    await start_mapping(call.ctx, call.query.mode)
    return {"result": True, "description": f"mapping started ({call.query.mode})"}


async def stop(call: Call[None, None]) -> Answer:
    """Stop mapping (Mapping → Busy → Free); cancels exploring first. What was not saved
    with POST /map/current_map_image is dropped."""
    await stop_mapping(call.ctx)
    return {"result": True, "description": "mapping stopped"}


async def stop_mapping(ctx: Context) -> None:
    """Mapping → Busy → Free: exploring cancelled, then the mapping node stopped."""
    slam = slam_port(ctx)
    core = ctx.core
    core.state.busy, core.state.mapping = True, False   # Mapping → Busy
    try:
        await slam.cancel_explore()
        await slam.stop()
    except BaseException:
        core.state.mapping = slam.mapping()
        raise
    finally:
        core.state.busy = False


async def _nav_point(ctx: Context, map_name: str, path: str, index: int) -> Pose2D:
    link = ctx.nav_services
    if not path:
        paths = await link.call(zm.ListPaths, zm.ListPathsRequest(map_name=map_name))
        names = sorted(p.path_name for p in paths.paths if p.map_name == map_name)
        if not names:
            raise ApiError(409, f"map {map_name!r} has no path with nav points: give "
                                "start_index only with a map that has one")
        path = names[0]
    res = await link.call(zm.GetNavPoints,
                          zm.GetNavPointsRequest(map_name=map_name, path_name=path))
    n = len(res.points)
    if not 0 <= index < n:
        has = f"has {n} (0..{n - 1})" if n else "has no nav points"
        raise ApiError(404, f"nav point {index} does not exist: path {path!r} of map "
                            f"{map_name!r} {has}")
    p = res.points[index]
    return Pose2D(x=p.x, y=p.y, theta=p.theta)


async def update(call: Call[None, UpdateQuery]) -> Answer:
    """Extend a saved map: relocalise at nav point ``start_index`` of ``path`` (or at the
    saved map's last pose), then keep mapping it."""
    q = call.query
    return {"result": True,
            "description": await extend_map(call.ctx, q.map, q.path, q.start_index)}


async def extend_map(ctx: Context, map_name: str = "", path: str = "",
                     start_index: int = -1) -> str:
    """Start extending ``map_name`` (default: nav's current map) from nav point
    ``start_index`` of ``path`` (-1: the saved map's last pose); says what it started."""
    slam = slam_port(ctx)
    _refuse_while_busy(ctx, slam)
    name = map_name or await ctx.nav_services.current_map()
    listed = await ctx.nav_services.call(zm.ListMaps, zm.ListMapsRequest(name=name))
    if not listed.maps:
        raise ApiError(404, f"unknown map {name!r}")
    pose = await _nav_point(ctx, name, path, start_index) if start_index >= 0 else None
    await _open(ctx, slam, "laser", name, pose)
    where = (f"nav point {start_index}" if pose is not None else "the saved map's last pose")
    return f"extending map {name!r} from {where}"


def _require_mapping(slam: SlamPort) -> None:
    if not slam.mapping():
        raise ApiError(409, "the robot is not mapping (state "
                            f"{slam.state().state!r}): GET /map/start first")


async def pose(call: Call[None, None]) -> Answer:
    """The robot in the map being built: ``x``, ``y`` (m), ``angle`` (rad)."""
    slam = slam_port(call.ctx)
    _require_mapping(slam)
    p = slam.pose()
    if p is None:
        raise ApiError(409, "mapping has started but placed no pose yet")
    return {"x": p.x, "y": p.y, "angle": p.theta}


def _grid(slam: SlamPort) -> Any:
    _require_mapping(slam)
    grid = slam.grid()
    if grid is None:
        raise ApiError(409, "mapping has started but no map has come yet (it comes with "
                            "the first scans)")
    return grid


async def current_map_image(call: Call[None, None]) -> Answer:
    """The map being built: ``map_params`` (origin, width, height, resolution) and the
    URL of its PNG."""
    grid = _grid(slam_port(call.ctx))
    info = grid.info
    o = info.origin.position
    prefix = call.path.removesuffix("/").removesuffix("/map/current_map_image")
    return {"status": "OK",
            "map_params": {"origin": [o.x, o.y, o.z], "width": info.width,
                           "height": info.height, "resolution": info.resolution},
            "map_image": f"{prefix}/map/current_map_png"}


async def save(call: Call[SaveBody, None]) -> Answer:
    """Save the map being built as ``name`` (``type`` floor or elevator, ``levels``): it is
    then in GET /navigation/saved_maps, with its PNG and PGM, ready to navigate on."""
    slam = slam_port(call.ctx)
    b = call.body
    _require_mapping(slam)
    name = await slam.save(b.name, b.type, b.levels)
    return {"result": True, "name": name}


class NativeMapping:
    """§12.3's mapping commands (``'V' 0x00..0x03``, from the serial port or
    ``galileo/cmds``) as the REST routes do them, with their refusals. ``'V' 0x02`` carries
    no name: the map is saved as ``map_<date>_<time>`` (the gateway host's local time), and
    then listed by GET /navigation/saved_maps like any other."""

    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx

    async def start(self) -> None:
        await start_mapping(self.ctx, "laser")

    async def stop(self) -> None:
        await stop_mapping(self.ctx)

    async def save(self) -> None:
        slam = slam_port(self.ctx)
        _require_mapping(slam)
        await slam.save(time.strftime("map_%Y%m%d_%H%M%S"), "floor", [])

    async def update(self) -> None:
        await extend_map(self.ctx)


async def current_map_png(call: Call[None, None]) -> Answer:
    """The map being built, as a PNG (white free, black occupied, grey unknown)."""
    return Response(grid_png(_grid(slam_port(call.ctx))), media_type="image/png")


async def track(call: Call[None, TrackQuery]) -> Answer:
    """The trajectory of this mapping, ``{x, y, z}`` each: recorded poses, or (with
    ``keyframes=true``) the pose graph's nodes where the last loop closure put them."""
    slam = slam_port(call.ctx)
    q = call.query
    return {"trajectory": [{"x": p.x, "y": p.y, "z": 0.0} for p in slam.track(q.keyframes)]}


def add_mapping_routes(api: Api) -> None:
    """Route the §5 map building operations to the mapping node (``call.ctx.slam``)."""
    result = {"result_style": True}
    api.add("GET", "/map/start", start, **result)
    api.add("GET", "/map/stop", stop, **result)
    api.add("GET", "/map/update", update, **result)
    api.add("GET", "/map/pose", pose)
    api.add("GET", "/map/current_map_image", current_map_image)
    api.add("POST", "/map/current_map_image", save, **result)
    api.add("GET", "/map/current_map_png", current_map_png, media_type="image/png")
    api.add("GET", "/map/track", track)
