"""REST ``/navigation/...`` goals and charging (docs/robot-api.md §6.4, §6.5).

Goals that the spec answers with a task (start_nav_task, move_to_index, multi_map_task,
loop_task, go_charge) are tasks of the tasks service, so they show in ``/task`` and are tracked,
paused and stopped like any other.
"""

from __future__ import annotations

from typing import Annotated

import msgspec
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.zenros_msgs.task_docs import as_document

from ...errors import Conflict
from ...ports.crossing import check_route
from ...ports.map_goal import check_goal_free
from ...state.core import NavUnavailable
from ..api import Answer, Api, ApiError, Call
from ..context import Context
from ..fields import Angle, Coord, Name, OptName
from .mapping import refuse_while_mapping

__all__ = ["add_goal_routes"]


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


class MapPoint(msgspec.Struct, forbid_unknown_fields=True):
    """A nav point of any map: ``level`` is taken and not used (a building file gives each
    floor map its level)."""

    map: Name
    index: Annotated[int, msgspec.Meta(ge=0, le=10000)]
    path: OptName = ""
    level: int = 0


class MultiMapBody(msgspec.Struct, forbid_unknown_fields=True):
    from_: MapPoint = msgspec.field(name="from")
    to: MapPoint = msgspec.field(name="to")


class LoopBody(msgspec.Struct, forbid_unknown_fields=True):
    wait_time: Annotated[float, msgspec.Meta(ge=0, le=86400)] = 0.0


async def only_path(ctx: Context, map_name: str) -> str:
    link = ctx.nav_services
    res = await link.call(zm.ListPaths, zm.ListPathsRequest(map_name=map_name))
    if len(res.paths) != 1:
        names = ", ".join(p.path_name for p in res.paths) or "none"
        raise ApiError(400, f"give the path: map {map_name!r} has {len(res.paths)} "
                            f"paths ({names})")
    return str(res.paths[0].path_name)


async def current_path(ctx: Context) -> str:
    """The current path (``/navigation/start?path=``, else the map's first); 409 when the
    map has none, 503 when nav does not answer."""
    try:
        return await ctx.nav_actions.current_path()
    except NavUnavailable as exc:
        raise ctx.core.presence.error("nav", str(exc)) from exc
    except ValueError as exc:
        raise ApiError(409, str(exc)) from exc


async def start_nav_task(call: Call[NavTaskBody, None]) -> Answer:
    """Go to ``x``, ``y``, ``theta`` (on ``map``: across maps through the point
    connections); returns the started navigation task."""
    nav = call.ctx.nav_actions
    link = call.ctx.nav_services
    run_task = call.ctx.tasks.run_task
    current_map = call.ctx.nav_services.current_map
    same_map = call.ctx.nav_actions.same_map
    b = call.body
    action = zm.NavAction(x=b.x, y=b.y, theta=b.theta)
    current = await current_map()
    if b.map and b.map != current:  # across maps (§6.7): the task finds the route
        await check_route(link, current, b.map)
        action.map = b.map
        nav.path_name = b.path
    else:
        same_map(b.map, b.path, current)
        check_goal_free(link.grid, b.x, b.y)  # 400 now, not a task that fails at planning
    return await run_task("navigation task", [action])


async def move_to_index(call: Call[None, IndexQuery]) -> Answer:
    """Go to nav point ``index`` of the current path, or of ``path`` on another
    ``map`` (across maps through the point connections); returns the started task."""
    refuse_while_mapping(call.ctx, "go to a nav point")
    nav = call.ctx.nav_actions
    link = call.ctx.nav_services
    run_task = call.ctx.tasks.run_task
    point = call.ctx.nav_actions.point
    current_map = call.ctx.nav_services.current_map
    same_map = call.ctx.nav_actions.same_map
    q = call.query
    current = await current_map()
    if q.map and q.map != current:  # across maps (§6.7): the task finds the route
        res = await link.call(zm.GetNavPoints, zm.GetNavPointsRequest(
            map_name=q.map, path_name=q.path or await only_path(call.ctx, q.map)))
        if not 0 <= q.index < len(res.points):
            n = len(res.points)
            raise ApiError(404, f"nav point {q.index} does not exist: path "
                                f"{res.path_name!r} of map {q.map!r} has {n}")
        await check_route(link, current, q.map)
        action = zm.NavAction(index=q.index, map=q.map, path=res.path_name)
        nav.path_name = res.path_name
    else:
        same_map(q.map, q.path, current)
        x, y, _ = await point(q.index)  # 404 now for a nav point that does not exist
        check_goal_free(link.grid, x, y, f"nav point {q.index}")
        action = zm.NavAction(index=q.index, path=await current_path(call.ctx))
    return await run_task("navigation task", [action])


async def _map_point(ctx: Context, p: MapPoint, start: str) -> zm.NavAction:
    """The nav_action to nav point ``p`` from map ``start``: 404 for a point that does not
    exist, 409 when no route of connections reaches its map."""
    link = ctx.nav_services
    names, _ = await link.maps()
    if names and p.map not in names:
        raise ApiError(404, f"unknown map {p.map!r}; known maps: {', '.join(names)}")
    res = await link.call(zm.GetNavPoints, zm.GetNavPointsRequest(
        map_name=p.map, path_name=p.path or await only_path(ctx, p.map)))
    if not 0 <= p.index < len(res.points):
        raise ApiError(404, f"nav point {p.index} does not exist: path {res.path_name!r} of "
                            f"map {p.map!r} has {len(res.points)}")
    if p.map != start:
        await check_route(link, start, p.map)
    return zm.NavAction(index=p.index, map=p.map, path=res.path_name)


async def multi_map_task(call: Call[MultiMapBody, None]) -> Answer:
    """Go to nav point ``from`` (on its map: across maps from the current one if need be),
    then to nav point ``to`` on its map, through the point connections (elevators
    included); returns the started task of two nav_actions."""
    refuse_while_mapping(call.ctx, "go to a nav point")
    b = call.body
    current = await call.ctx.nav_services.current_map()
    first = await _map_point(call.ctx, b.from_, current)
    second = await _map_point(call.ctx, b.to, b.from_.map)
    return await call.ctx.tasks.run_task("multi-map task", [first, second])


async def stop_nav_task(call: Call[None, None]) -> Answer:
    """Stop the running (navigation) task; returns it."""
    tasks = call.ctx.tasks
    return as_document(await tasks.step("stop"))


async def get_loop(call: Call[None, None]) -> Answer:
    """The patrol (loop) task, or 404 when none is running."""
    nav, tasks = call.ctx.nav_actions, call.ctx.tasks
    if not nav.loop_task_id:
        raise ApiError(404, "no loop task: POST /navigation/loop_task starts one")
    return as_document(await tasks.get(nav.loop_task_id))


async def post_loop(call: Call[LoopBody, None]) -> Answer:
    """Patrol every nav point of the current path, waiting ``wait_time`` s at each."""
    refuse_while_mapping(call.ctx, "start a loop task")
    core = call.ctx.core
    nav = call.ctx.nav_actions
    link = call.ctx.nav_services
    run_task = call.ctx.tasks.run_task
    b = call.body
    path = await current_path(call.ctx)
    res = await link.call(zm.GetNavPoints, zm.GetNavPointsRequest(path_name=path))
    if not res.points:
        raise ApiError(409, f"path {res.path_name!r} has no nav points to patrol")
    subs: list[zm.Action] = []
    for i in range(len(res.points)):  # by index: each leg names its nav point (§4 targetNumID)
        subs.append(zm.NavAction(index=i, path=res.path_name))
        if b.wait_time > 0:
            subs.append(zm.SleepAction(wait_time=b.wait_time))
    task = await run_task("loop task", subs, loop=True)
    nav.loop_task_id = task["id"]
    core.state.looping = True
    return task


async def delete_loop(call: Call[None, None]) -> Answer:
    """Stop patrolling; returns the stopped loop task."""
    core, nav, tasks = call.ctx.core, call.ctx.nav_actions, call.ctx.tasks
    if not nav.loop_task_id:
        raise ApiError(404, "no loop task is running")
    task = as_document(await tasks.step("stop", nav.loop_task_id))
    nav.loop_task_id = ""
    core.state.looping = False
    return task


async def go_charge(call: Call[None, None]) -> Answer:
    """Go to the charging station and dock; returns the task (one ``charge_action``)."""
    refuse_while_mapping(call.ctx, "go to charge")
    link, run_task = call.ctx.nav_services, call.ctx.tasks.run_task
    res = await link.call(zm.GetChargePose, zm.GetChargePoseRequest())
    if not res.is_set:
        raise ApiError(409, f"map {res.map_name!r} has no charge pose: "
                            "POST /navigation/charge_pose first")
    p = res.pose
    return await run_task("charge task", [zm.ChargeAction(x=p.x, y=p.y, theta=p.theta)])


async def stop_charge(call: Call[None, None]) -> Answer:
    """Stop charging, whatever the task state: stops the running task (the charge task,
    while it docks) if there is one, and undocks; ``task`` is the stopped task or null."""
    core, nav, tasks = call.ctx.core, call.ctx.nav_actions, call.ctx.tasks
    task = None
    running = [t for t in await tasks.tasks() if t.state in ("WORKING", "PAUSED")]
    if running:
        try:
            task = as_document(await tasks.step("stop", running[0].id))
        except Conflict:  # it ended meanwhile: nothing left to stop
            pass
    try:
        await nav.stop_charge()
    except NavUnavailable as exc:
        raise core.presence.error("nav", str(exc)) from exc
    return {"status": "ok", "task": task}


async def get_charge_pose(call: Call[None, None]) -> Answer:
    """The stored charging-station pose: ``x``, ``y``, ``theta``."""
    link = call.ctx.nav_services
    res = await link.call(zm.GetChargePose, zm.GetChargePoseRequest())
    if not res.is_set:
        raise ApiError(404, f"map {res.map_name!r} has no charge pose yet")
    return {"x": res.pose.x, "y": res.pose.y, "theta": res.pose.theta}


async def post_charge_pose(call: Call[None, None]) -> Answer:
    """Store the robot's current pose as the charging-station pose."""
    refuse_while_mapping(call.ctx, "set the charge pose")
    link = call.ctx.nav_services
    res = await link.call(zm.SetChargePose,
                          zm.SetChargePoseRequest(use_current_pose=True))
    return {"x": res.pose.x, "y": res.pose.y, "theta": res.pose.theta}


def add_goal_routes(api: Api) -> None:
    """Route the goal, patrol and charging operations."""
    api.add("POST", "/navigation/start_nav_task", start_nav_task)
    api.add("GET", "/navigation/move_to_index", move_to_index)
    api.add("POST", "/navigation/multi_map_task", multi_map_task)
    api.add("GET", "/navigation/stop_nav_task", stop_nav_task)
    api.add("GET", "/navigation/loop_task", get_loop)
    api.add("POST", "/navigation/loop_task", post_loop)
    api.add("DELETE", "/navigation/loop_task", delete_loop)
    api.add("GET", "/navigation/go_charge", go_charge)
    api.add("GET", "/navigation/stop_charge", stop_charge)
    api.add("GET", "/navigation/charge_pose", get_charge_pose)
    api.add("POST", "/navigation/charge_pose", post_charge_pose)
