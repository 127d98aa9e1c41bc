"""REST ``/navigation/...`` lifecycle, pose, maps and goals (§6.1-§6.5, §6.9).

Goals that the spec answers with a task (start_nav_task, move_to_index, loop_task,
go_charge) are tasks of the tasks service, so they show in ``/task`` and are tracked,
paused and stopped like any other.
"""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from starlette.responses import Response
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.geometry_msgs import PoseWithCovarianceStamped
from zenros.msgs.std_msgs import Header

from .api import Api, ApiError, Call
from .core import Core, NavUnavailable
from .map_image import grid_pgm, grid_png
from .nav_link import NavLink
from .navigator import Navigator, pose_stamped
from .rest_tasks import TaskCaller

__all__ = ["Name", "OptName", "add_nav_routes"]

Name = Annotated[str, msgspec.Meta(pattern=r"^[A-Za-z0-9_][A-Za-z0-9_.\-]{0,63}$")]
OptName = Annotated[str, msgspec.Meta(pattern=r"^([A-Za-z0-9_][A-Za-z0-9_.\-]{0,63})?$")]
Coord = Annotated[float, msgspec.Meta(ge=-1e5, le=1e5)]
Angle = Annotated[float, msgspec.Meta(ge=-100.0, le=100.0)]
_ENC = msgspec.json.Encoder()
OWN_TASKS = frozenset({"navigation task", "loop task", "charge task"})


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


class NavTaskBody(msgspec.Struct, forbid_unknown_fields=True):
    x: Coord
    y: Coord
    theta: Angle = 0.0
    map: OptName = ""
    path: OptName = ""


class IndexQuery(msgspec.Struct, forbid_unknown_fields=True):
    index: Annotated[int, msgspec.Meta(ge=0, le=10000)]
    map: OptName = ""
    path: OptName = ""
    level: int = 0


class LoopBody(msgspec.Struct, forbid_unknown_fields=True):
    wait_time: Annotated[float, msgspec.Meta(ge=0, le=86400)] = 0.0


def add_nav_routes(api: Api, core: Core, nav: Navigator, link: NavLink,
                   tasks: TaskCaller) -> None:
    """Route the navigation operations backed by the nav and tasks services."""
    loop_ids: list[str] = []

    async def task_call(name: str, ident: str = "", body: Any = None) -> Any:
        code, message, text = await tasks(name, ident, "" if body is None
                                          else _ENC.encode(body).decode())
        if code != 200:
            raise ApiError(code, message or f"tasks/{name} failed ({code})")
        return msgspec.json.decode(text)

    async def run_task(name: str, sub_tasks: list[dict[str, Any]], loop: bool = False
                       ) -> dict[str, Any]:
        """Create and start a task; a running navigation task of ours gives way to it (a new
        goal replaces the old one), any other running task is a 409."""
        task = await task_call("create", "", {"name": name, "sub_tasks": sub_tasks,
                                              "loop_flag": loop})
        try:
            started: dict[str, Any] = await task_call("start", task["id"])
            return started
        except ApiError as exc:
            if exc.status_code != 409:
                raise
            running = [t for t in await task_call("get")
                       if t.get("state") in ("WORKING", "PAUSED")]
            if not running or any(t.get("name") not in OWN_TASKS for t in running):
                await task_call("delete", task["id"])
                raise
            for t in running:
                await task_call("stop", t["id"])
            restarted: dict[str, Any] = await task_call("start", task["id"])
            return restarted

    async def point(index: int) -> tuple[float, float, float]:
        try:
            return await nav.nav_point(index)
        except NavUnavailable as exc:
            raise ApiError(503, str(exc)) from exc
        except ValueError as exc:
            raise ApiError(404 if "does not exist" in str(exc) else 409, str(exc)) from exc

    async def current_map() -> str:
        res = await link.call("map_server/current_map", zm.GetCurrentMapRequest())
        return str(res.name)

    def same_map(map_name: str, path: str, current: str) -> None:
        if map_name and map_name != current:
            raise ApiError(400, f"map {map_name!r} is not the current map {current!r}: "
                                "cross-map navigation is not supported; switch_map first")
        if path and path != nav.path_name:
            nav.path_name = path

    # ------------------------------------------------------------------ lifecycle

    async def start(call: Call) -> Any:
        """Start navigation (optionally on ``map``/``path``, relocalised at ``start_index``)."""
        q: StartQuery = call.query
        if not nav.available():
            raise ApiError(503, "navigation is not available: the nav service is not running")
        core.state.busy = True  # §7: Busy while the map loads and the robot relocalises
        try:
            if q.map and q.map != await current_map():
                res = await link.call("switch_map", zm.SwitchMapRequest(map_name=q.map))
                if not res.success:
                    raise ApiError(400, res.message)
            if q.path:
                nav.path_name = q.path
            if q.start_index >= 0:
                x, y, th = await point(q.start_index)
                publish_initialpose(x, y, th)
        finally:
            core.state.busy = False
        nav.stopped = False
        core.state.nav_open = True
        return {"result": True, "description": "navigation started"}

    async def reload(call: Call) -> Any:
        """Load ``map`` (when not loaded) and make ``path`` the current path."""
        q: ReloadQuery = call.query
        if q.map != await current_map():
            res = await link.call("switch_map", zm.SwitchMapRequest(map_name=q.map))
            if not res.success:
                raise ApiError(400, res.message)
        if q.path:
            nav.path_name = q.path
        return {"status": "ok", "map": q.map, "path": q.path}

    async def stop(call: Call) -> Any:
        """Stop navigation: cancel the goal; navStatus goes to 0."""
        if nav.available():
            try:
                await nav.cancel()
            except NavUnavailable as exc:
                raise ApiError(503, str(exc)) from exc
        nav.stopped = True
        core.state.nav_open = False
        return {"result": True, "description": "navigation stopped"}

    def publish_initialpose(x: float, y: float, theta: float) -> None:
        msg = PoseWithCovarianceStamped(header=Header(frame_id="map"))
        msg.pose.pose = pose_stamped(x, y, theta).pose
        link.initialpose.publish(msg)

    # ------------------------------------------------------------------ queries

    async def pose(call: Call) -> Any:
        """Robot pose in ``map``: ``x``, ``y`` (m), ``angle`` (rad); -1 while unknown."""
        st = core.status
        return {"x": st.currentPosX, "y": st.currentPosY, "angle": st.currentAngle}

    async def current_path(call: Call) -> Any:
        """The loaded ``map`` and ``path``."""
        try:
            path = await nav.current_path()
        except ValueError:
            path = ""
        return {"map": await current_map(), "path": path}

    async def target_distance(call: Call) -> Any:
        """Distance (m) to the current goal; -1 without one."""
        return {"distance": core.status.targetDistance}

    # ------------------------------------------------------------------ maps

    def map_object(m: Any) -> dict[str, Any]:
        return {"name": m.name, "resolution": m.resolution, "origin": list(m.origin),
                "occupied_thresh": m.occupied_thresh, "free_thresh": m.free_thresh,
                "negate": m.negate, "md5sum": m.md5sum, "type": m.type,
                "levels": list(m.levels), "slam_type": m.slam_type}

    async def saved_maps(call: Call) -> Any:
        """The stored maps (§6.3 map objects), optionally one ``name`` or one slam ``type``."""
        q: SavedMapsQuery = call.query
        res = await link.call("map_server/list_maps", zm.ListMapsRequest(name=q.name))
        return [map_object(m) for m in res.maps if not q.type or m.slam_type == q.type]

    async def get_current_map(call: Call) -> Any:
        """The map in use: ``name`` and ``md5sum``."""
        res = await link.call("map_server/current_map", zm.GetCurrentMapRequest())
        return {"name": res.name, "md5sum": res.md5sum}

    async def loaded_grid(name: str) -> Any:
        """The loaded map's grid; ``name`` must be it (or empty)."""
        current = await current_map()
        if name and name != current:
            listed = await link.call("map_server/list_maps", zm.ListMapsRequest(name=name))
            if not listed.maps:
                raise ApiError(404, f"unknown map {name!r}")
            raise ApiError(409, f"map {name!r} is stored but not loaded; the gateway renders "
                                f"the loaded map ({current!r}): switch_map first")
        if link.grid is None:
            raise ApiError(503, "no map received from the nav service yet")
        return link.grid

    async def map_png(call: Call) -> Any:
        """The current map as a PNG image (``name`` must be the current map or empty)."""
        return Response(grid_png(await loaded_grid(call.query.name)), media_type="image/png")

    async def map_pgm(call: Call) -> Any:
        """The current map as a PGM image (``name`` must be the current map or empty)."""
        return Response(grid_pgm(await loaded_grid(call.query.name)),
                        media_type="image/x-portable-graymap")

    async def robot_tracks(call: Call) -> Any:
        """Where the robot has been on ``map_name`` (default: the current map), one
        ``{x, y, z}`` a second, the last hour, since the gateway started."""
        name = call.query.map_name or await current_map()
        return {"map_name": name,
                "track": [{"x": x, "y": y, "z": 0.0} for x, y in nav.tracks.get(name, ())]}

    async def switch_map(call: Call) -> Any:
        """Load another stored map."""
        res = await link.call("switch_map", zm.SwitchMapRequest(map_name=call.query.map_name))
        if not res.success:
            raise ApiError(400, res.message)
        return {"status": "ok"}

    async def init_pose(call: Call) -> Any:
        """Set the robot's pose for relocalisation (``z`` is the heading)."""
        b: InitPose = call.body
        publish_initialpose(b.x, b.y, b.z)
        return {"status": "ok"}

    # ------------------------------------------------------------------ goals (tasks)

    async def start_nav_task(call: Call) -> Any:
        """Go to ``x``, ``y``, ``theta``; returns the started navigation task."""
        b: NavTaskBody = call.body
        same_map(b.map, b.path, await current_map())
        task = await run_task("navigation task", [
            {"type": "nav_action", "x": b.x, "y": b.y, "theta": b.theta}])
        core.state.goal.num_id = -2
        return task

    async def move_to_index(call: Call) -> Any:
        """Go to nav point ``index`` of the current path; returns the started task."""
        q: IndexQuery = call.query
        same_map(q.map, q.path, await current_map())
        x, y, th = await point(q.index)
        task = await run_task("navigation task", [
            {"type": "nav_action", "x": x, "y": y, "theta": th}])
        core.state.goal.num_id = q.index
        return task

    async def stop_nav_task(call: Call) -> Any:
        """Stop the running (navigation) task; returns it."""
        return await task_call("stop")

    async def get_loop(call: Call) -> Any:
        """The patrol (loop) task, or 404 when none was started."""
        if not loop_ids:
            raise ApiError(404, "no loop task: POST /navigation/loop_task starts one")
        return await task_call("get", loop_ids[-1])

    async def post_loop(call: Call) -> Any:
        """Patrol every nav point of the current path, waiting ``wait_time`` s at each."""
        b: LoopBody = call.body
        try:
            path = await nav.current_path()
        except ValueError as exc:
            raise ApiError(409, str(exc)) from exc
        res = await link.call("get_nav_points", zm.GetNavPointsRequest(path_name=path))
        if not res.points:
            raise ApiError(409, f"path {res.path_name!r} has no nav points to patrol")
        subs: list[dict[str, Any]] = []
        for p in res.points:
            subs.append({"type": "nav_action", "x": p.x, "y": p.y, "theta": p.theta})
            if b.wait_time > 0:
                subs.append({"type": "sleep_action", "wait_time": b.wait_time})
        task = await run_task("loop task", subs, loop=True)
        loop_ids.append(task["id"])
        nav.loop_task_id = task["id"]
        core.state.looping = True
        return task

    async def delete_loop(call: Call) -> Any:
        """Stop patrolling; returns the stopped loop task."""
        if not loop_ids:
            raise ApiError(404, "no loop task is running")
        task = await task_call("stop", loop_ids[-1])
        nav.loop_task_id = ""
        core.state.looping = False
        return task

    async def go_charge(call: Call) -> Any:
        """Go to the charging station and dock; returns the task (one ``charge_action``)."""
        res = await link.call("get_charge_pose", zm.GetChargePoseRequest())
        if not res.is_set:
            raise ApiError(409, f"map {res.map_name!r} has no charge pose: "
                                "POST /navigation/charge_pose first")
        p = res.pose
        return await run_task("charge task", [
            {"type": "charge_action", "x": p.x, "y": p.y, "theta": p.theta}])

    async def stop_charge(call: Call) -> Any:
        """Stop charging: stops the charge task and undocks."""
        task = await task_call("stop")
        try:
            await nav.stop_charge()
        except NavUnavailable as exc:
            raise ApiError(503, str(exc)) from exc
        return {"status": "ok", "task": task}

    async def get_charge_pose(call: Call) -> Any:
        """The stored charging-station pose: ``x``, ``y``, ``theta``."""
        res = await link.call("get_charge_pose", zm.GetChargePoseRequest())
        if not res.is_set:
            raise ApiError(404, f"map {res.map_name!r} has no charge pose yet")
        return {"x": res.pose.x, "y": res.pose.y, "theta": res.pose.theta}

    async def post_charge_pose(call: Call) -> Any:
        """Store the robot's current pose as the charging-station pose."""
        res = await link.call("set_charge_pose",
                              zm.SetChargePoseRequest(use_current_pose=True))
        return {"x": res.pose.x, "y": res.pose.y, "theta": res.pose.theta}

    result = {"result_style": True}
    api.add("GET", "/navigation/start", start, query=StartQuery, **result)
    api.add("GET", "/navigation/stop", stop, **result)
    api.add("GET", "/navigation/reload", reload, query=ReloadQuery)
    api.add("GET", "/navigation/pose", pose)
    api.add("GET", "/navigation/current_path", current_path)
    api.add("GET", "/navigation/target_distance", target_distance)
    api.add("GET", "/navigation/saved_maps", saved_maps, query=SavedMapsQuery)
    api.add("GET", "/navigation/current_map", get_current_map)
    api.add("GET", "/navigation/map_png", map_png, query=NamedMap, media_type="image/png")
    api.add("GET", "/navigation/map_pgm", map_pgm, query=NamedMap,
            media_type="image/x-portable-graymap")
    api.add("GET", "/navigation/robot_tracks", robot_tracks, query=TrackQuery)
    api.add("GET", "/navigation/switch_map", switch_map, query=SwitchQuery)
    api.add("POST", "/navigation/init_pose", init_pose, body=InitPose)
    api.add("POST", "/navigation/start_nav_task", start_nav_task, body=NavTaskBody)
    api.add("GET", "/navigation/move_to_index", move_to_index, query=IndexQuery)
    api.add("GET", "/navigation/stop_nav_task", stop_nav_task)
    api.add("GET", "/navigation/loop_task", get_loop)
    api.add("POST", "/navigation/loop_task", post_loop, body=LoopBody)
    api.add("DELETE", "/navigation/loop_task", delete_loop)
    api.add("GET", "/navigation/go_charge", go_charge)
    api.add("GET", "/navigation/stop_charge", stop_charge)
    api.add("GET", "/navigation/charge_pose", get_charge_pose)
    api.add("POST", "/navigation/charge_pose", post_charge_pose)
