"""REST ``/system/slide_*`` and ``/system/jacking_*`` (docs/robot-api.md §3.10): the slide
rail, the jacking lift and its rotation, from the chassis's ``actuators/state``.

A reading is the axis's latest state. A ``*_move_to`` is a task of the tasks service holding
one ``slide_action``, ``jacking_action`` or ``jacking_rotate_action`` (§9.2), so it shows in
``/task`` with its progress and is paused and stopped like any other; a target past the
axis's travel, a speed past its maximum or an axis not homed is refused at once (400, 409)
with the reason, before any task is made. A new move of an axis replaces a running move task
of the same axis; any other running task is a 409.
"""

from __future__ import annotations

import json
import math
from typing import Annotated, Any, Literal, NamedTuple

import msgspec
from zenros.msgs.zenros_msgs.task_actions import (
    JackingAction,
    JackingRotateAction,
    SlideAction,
)

from ..api import Answer, Api, ApiError, Call
from ..context import Context
from ..fields import Angle
from .extras import latest

__all__ = ["add_actuator_routes"]

Metres = Annotated[float, msgspec.Meta(ge=-100.0, le=100.0)]
Speed = Annotated[float, msgspec.Meta(ge=0.0, le=100.0)]


class AngleQuery(msgspec.Struct, forbid_unknown_fields=True):
    frame_id: Literal["", "base_link", "map"] = ""


class PoseMove(msgspec.Struct, forbid_unknown_fields=True):
    pose: Metres
    speed: Speed = 0.0


class AngleMove(msgspec.Struct, forbid_unknown_fields=True):
    angle: Angle
    speed: Speed = 0.0
    frame_id: Literal["base_link", "map"] = "base_link"


class AxisState(NamedTuple):
    zero_status: int
    position: float
    low: float
    high: float
    max_speed: float

    @property
    def ratio(self) -> float:
        return (self.position - self.low) / (self.high - self.low)


async def _axis(ctx: Context, name: str) -> AxisState:
    """Actuator axis ``name`` from the chassis's ``actuators/state``; 404 when the robot has
    no actuators in the graph, or not this axis."""
    hub = ctx.hub
    state: dict[str, Any] = json.loads(await latest(hub, hub.resolve("actuators/state")))
    try:
        i = state["name"].index(name)
    except ValueError:
        raise ApiError(404, f"the robot has no {name} axis") from None
    max_speed = state.get("max_speed") or [math.inf] * len(state["name"])
    return AxisState(int(state["zero_status"][i]), float(state["position"][i]),
                     float(state["low"][i]), float(state["high"][i]), float(max_speed[i]))


def _pose(axis: AxisState) -> Answer:
    return {"zero_status": axis.zero_status, "current_pose": round(axis.position, 4),
            "pose_ratio": round(axis.ratio, 4)}


async def slide_pose(call: Call[None, None]) -> Answer:
    """The slide rail: ``zero_status`` (0 homing, 1 homed, -1 error), ``current_pose`` (m),
    ``pose_ratio`` (0-1 of its travel)."""
    return _pose(await _axis(call.ctx, "slide"))


async def jacking_pose(call: Call[None, None]) -> Answer:
    """The jacking lift: ``zero_status``, ``current_pose`` (m), ``pose_ratio``."""
    return _pose(await _axis(call.ctx, "jacking"))


def _heading(ctx: Context) -> float:
    pose = ctx.core.state.pose
    if pose is None:
        raise ApiError(503, "the robot's pose in map is unknown (is nav running?)")
    return float(pose[2])


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


async def jacking_angle(call: Call[None, AngleQuery]) -> Answer:
    """The lift's rotation: ``zero_status``, ``current_angle`` (rad) in ``base_link``
    (default) or ``map`` (plus the robot's heading; 503 while its pose is unknown)."""
    axis = await _axis(call.ctx, "jacking_rotation")
    angle = axis.position
    if call.query.frame_id == "map":
        angle = _wrap(angle + _heading(call.ctx))
    return {"zero_status": axis.zero_status, "current_angle": round(angle, 4)}


def _check(name: str, axis: AxisState, target: float, speed: float, unit: str) -> None:
    if axis.zero_status != 1:
        raise ApiError(409, f"the {name} is not homed (zero_status {axis.zero_status}): it "
                            "moves once homed")
    if not axis.low <= target <= axis.high:
        raise ApiError(400, f"the {name} cannot go to {target:g} {unit}: past its travel "
                            f"[{axis.low:g}, {axis.high:g}]")
    if speed > axis.max_speed:
        raise ApiError(400, f"the {name}'s speed {speed:g} is above its maximum "
                            f"{axis.max_speed:g} {unit}/s")


async def _run(ctx: Context, name: str, action: SlideAction | JackingRotateAction) -> Answer:
    return await ctx.tasks.run_task(name, [action], replaces=frozenset({name}))


async def slide_move_to(call: Call[None, PoseMove]) -> Answer:
    """Move the slide rail to ``pose`` (m) at ``speed`` (m/s, 0: its default); returns the
    task (one ``slide_action``)."""
    q = call.query
    _check("slide rail", await _axis(call.ctx, "slide"), q.pose, q.speed, "m")
    return await _run(call.ctx, "slide_task", SlideAction(mode=3, pose=q.pose, speed=q.speed))


async def jacking_move_to(call: Call[None, PoseMove]) -> Answer:
    """Move the lift to ``pose`` (m) at ``speed`` (m/s, 0: its default); returns the task
    (one ``jacking_action``)."""
    q = call.query
    _check("lift", await _axis(call.ctx, "jacking"), q.pose, q.speed, "m")
    return await _run(call.ctx, "jacking_task",
                      JackingAction(mode=3, pose=q.pose, speed=q.speed))


async def jacking_angle_move_to(call: Call[None, AngleMove]) -> Answer:
    """Turn the lift's top to ``angle`` (rad) in ``frame_id`` (``base_link``, or ``map``)
    at ``speed`` (rad/s, 0: its default); returns the task (one ``jacking_rotate_action``)."""
    q = call.query
    axis = await _axis(call.ctx, "jacking_rotation")
    target = q.angle if q.frame_id == "base_link" else _wrap(q.angle - _heading(call.ctx))
    _check("lift rotation", axis, target, q.speed, "rad")
    return await _run(call.ctx, "jacking_rotate_task", JackingRotateAction(
        mode=3, angle=q.angle, speed=q.speed, frame_id=q.frame_id))


def add_actuator_routes(api: Api) -> None:
    """Route §3.10's readings and moves."""
    api.add("GET", "/system/slide_pose", slide_pose)
    api.add("GET", "/system/jacking_pose", jacking_pose)
    api.add("GET", "/system/jacking_angle", jacking_angle)
    api.add("GET", "/system/slide_move_to", slide_move_to)
    api.add("GET", "/system/jacking_move_to", jacking_move_to)
    api.add("GET", "/system/jacking_angle_move_to", jacking_angle_move_to)
