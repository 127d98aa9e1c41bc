"""REST ``/navigation/start_local_move*`` (docs/robot-api.md §6.10): relative moves without the
global planner.

Each creates and starts a task of the tasks service holding the spec's actions (§9.2):
``local_move_action`` (nav's ``drive_on_heading`` and ``spin``), ``local_move_target_action``
(nav's ``local_move_target``), after a ``nav_action`` to a nav point and before an
``io_action`` where the spec says so. A running task of the gateway's own (a navigation,
loop, charge or local move task) gives way to the new one; any other running task is a 409.
"""

from __future__ import annotations

from typing import Annotated, Literal

import msgspec
from zenros.msgs.zenros_msgs.task_actions import (
    IoAction,
    LocalMoveAction,
    LocalMoveTargetAction,
    NavAction,
)

from ..api import Answer, Api, Call
from ..context import Context
from ..fields import Angle, Coord

__all__ = ["TASK_NAME", "add_local_move_routes"]

TASK_NAME = "local move task"

Distance = Annotated[float, msgspec.Meta(ge=-20.0, le=20.0)]
Index = Annotated[int, msgspec.Meta(ge=0, le=10000)]
Tolerance = Annotated[float, msgspec.Meta(gt=0.0, le=10.0)]


class MoveQuery(msgspec.Struct, forbid_unknown_fields=True):
    distance: Distance = 0.0
    angle: Angle = 0.0
    method: Literal[0, 1] = 0


class NavMoveQuery(msgspec.Struct, forbid_unknown_fields=True):
    index: Index
    distance: Distance = 0.0
    angle: Angle = 0.0
    method: Literal[0, 1] = 0


class NavMoveIoQuery(msgspec.Struct, forbid_unknown_fields=True):
    index: Index
    level: Literal["0", "1"]
    port: Literal["1", "2", "3"]
    distance: Distance = 0.0
    angle: Angle = 0.0
    method: Literal[0, 1] = 0


class TargetQuery(msgspec.Struct, forbid_unknown_fields=True):
    x: Coord
    y: Coord
    theta: Angle = 0.0
    frame_id: Literal["map", "base_link"] = "map"
    xy_tolerance: Tolerance = 0.05
    yaw_tolerance: Annotated[float, msgspec.Meta(gt=0.0, le=3.15)] = 0.05
    timeout: Annotated[float, msgspec.Meta(ge=0.0, le=86400.0)] = 0.0
    start_rotate_enable: bool = True
    target_rotate_enable: bool = True


class TargetIndexQuery(msgspec.Struct, forbid_unknown_fields=True):
    index: Index
    start_rotate_enable: bool = True
    target_rotate_enable: bool = True


def _move(q: MoveQuery | NavMoveQuery | NavMoveIoQuery) -> LocalMoveAction:
    return LocalMoveAction(distance=q.distance, angle=q.angle, method=q.method)


async def nav_to(ctx: Context, index: int) -> NavAction:
    x, y, theta = await ctx.nav_actions.point(index)
    return NavAction(x=x, y=y, theta=theta)


async def start_local_move(call: Call[None, MoveQuery]) -> Answer:
    """Move ``distance`` m (+ forward) and turn ``angle`` rad (+ CCW) from where the
    robot is; ``method`` 0 moves then turns, 1 turns then moves. Returns the task."""
    tasks = call.ctx.tasks
    return await tasks.run_task(TASK_NAME, [_move(call.query)])


async def start_nav_and_local_move(call: Call[None, NavMoveQuery]) -> Answer:
    """Go to nav point ``index``, then make the local move. Returns the task."""
    tasks = call.ctx.tasks
    q = call.query
    return await tasks.run_task(TASK_NAME, [await nav_to(call.ctx, q.index), _move(q)])


async def start_nav_local_move_io(call: Call[None, NavMoveIoQuery]) -> Answer:
    """Go to nav point ``index``, make the local move, then set output ``port`` to
    ``level``. Returns the task."""
    tasks = call.ctx.tasks
    q = call.query
    return await tasks.run_task(TASK_NAME, [
        await nav_to(call.ctx, q.index), _move(q),
        IoAction(level=q.level, port=q.port)])


async def start_local_move_target(call: Call[None, TargetQuery]) -> Answer:
    """A precise short move to (``x``, ``y``, ``theta``) in ``map`` or relative to
    ``base_link``, without the planner. Returns the task."""
    tasks = call.ctx.tasks
    q = call.query
    return await tasks.run_task(TASK_NAME, [
        LocalMoveTargetAction(**msgspec.structs.asdict(q))])


async def start_local_move_index(call: Call[None, TargetIndexQuery]) -> Answer:
    """A precise short move to nav point ``index`` without the planner. Returns the
    task."""
    tasks = call.ctx.tasks
    q = call.query
    x, y, theta = await call.ctx.nav_actions.point(q.index)
    return await tasks.run_task(TASK_NAME, [LocalMoveTargetAction(
        x=x, y=y, theta=theta, frame_id="map", start_rotate_enable=q.start_rotate_enable,
        target_rotate_enable=q.target_rotate_enable)])


def add_local_move_routes(api: Api) -> None:
    """Route the five local-move operations."""
    api.add("GET", "/navigation/start_local_move", start_local_move)
    api.add("GET", "/navigation/start_nav_and_local_move", start_nav_and_local_move)
    api.add("GET", "/navigation/start_nav_local_move_io", start_nav_local_move_io)
    api.add("GET", "/navigation/start_local_move_target", start_local_move_target)
    api.add("GET", "/navigation/start_local_move_index", start_local_move_index)
