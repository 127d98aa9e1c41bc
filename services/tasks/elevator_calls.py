"""The elevator task actions (docs/tasks.md, "Elevator actions"): ``elevator_req_action``,
``lbt_elevator_req_action`` and ``lbt_elevator_ack_action`` on the building's elevator
controller (docs/building.md), through `ElevatorLink`.

The controller speaks the robots' holder protocol (``call``, ``go``, ``release``); the
robot API's requests map onto it:

- ``elevator_req_action`` (``level``): ``call`` to ``level``; complete once the car stands
  there open for this robot (``WAITING_IN``: it holds its doors for the robot).
- ``lbt_elevator_req_action`` ``enter``: the same ``call`` to ``from_level``; the doors stay
  held until the ack. Its ack is ``go`` to ``to_level`` (the robot is inside).
- ``lbt_elevator_req_action`` ``leave``: wait until the car stands open at ``to_level`` for
  this robot (``WAITING_OUT``: the doors held until the ack), then switch nav to that floor's
  map at the same place in the car. Its ack is ``release`` (the robot is out).

A cancel while waiting releases the claim; a claim still held when the task ends is released
(the controller never carries a robot that does not hold the car, nor closes its doors on
one, so a release is always safe). A claim the robot never uses also lapses after the car's
``hold_s``.
"""

from __future__ import annotations

from collections.abc import Callable

from zenros.building import Elevator
from zenros.msgs.zenros_msgs import ElevatorState
from zenros.msgs.zenros_msgs.task_actions import (
    ElevatorReqAction,
    LbtElevatorAckAction,
    LbtElevatorReqAction,
)
from zenros.se2 import Pose2

from .context import Context
from .elevator_link import ElevatorLink, LbtRequest
from .outcome import Outcome

__all__ = ["elevator_req", "lbt_elevator_ack", "lbt_elevator_req"]

OPEN = 0.999  # the car's doors count as open from here
AT_FLOOR = 0.01


def _car(ctx: Context, name: str, *levels: int) -> tuple[ElevatorLink, Elevator] | Outcome:
    """The link and car ``name`` ("": the first) serving ``levels``, or why not."""
    lift = ctx.robot.elevators
    if lift is None:
        return Outcome("error", "no building: the tasks service was started without "
                                "building:=PATH (docs/building.md), so it knows no elevator")
    try:
        e = lift.building.elevator(name)
    except LookupError as exc:
        return Outcome("error", str(exc))
    for level in levels:
        if level not in e.levels:
            return Outcome("error", f"elevator {e.name} does not serve level {level} (levels "
                                    f"{', '.join(str(lv) for lv in e.levels)})")
    if not lift.available(e.name):
        return Outcome("error", f"no elevator controller serves elevator {e.name} (is the "
                                "elevator service of the building running? docs/building.md)")
    return lift, e


def _deadline(ctx: Context, timeout: float) -> Callable[[], bool]:
    if timeout <= 0:
        return lambda: False
    end = ctx.robot.now() + timeout
    return lambda: ctx.robot.now() > end


def _open_for(me: str, level: int, state: str) -> Callable[[ElevatorState], bool]:
    return lambda s: (s.holder == me and s.state == state and s.level == level
                      and abs(s.position - level) < AT_FLOOR and s.door >= OPEN)


def _release_if_mine(lift: ElevatorLink, name: str) -> None:
    s = lift.state(name)
    if s is not None and (s.holder == lift.me or lift.me in s.queue):
        lift.command(name, "release")


def _call(ctx: Context, lift: ElevatorLink, e: Elevator, level: int,
          timeout: float) -> Outcome:
    """Call car ``e`` to ``level`` for this robot and wait until it stands there open."""
    s = lift.state(e.name)
    if not (s is not None and _open_for(lift.me, level, "WAITING_IN")(s)):
        if s is not None and s.holder == lift.me:
            return Outcome("error", f"this robot holds elevator {e.name} already (state "
                                    f"{s.state} at level {s.level}); release it first")
        out = lift.command(e.name, "call", level)
        if out.name != "complete":
            return out
        ctx.at_end(lambda: _release_if_mine(lift, e.name))
        ctx.item.result = f"called elevator {e.name} to level {level}"
        ctx.changed()
    out = lift.wait(e.name, _open_for(lift.me, level, "WAITING_IN"),
                    f"elevator {e.name} open at level {level}", _deadline(ctx, timeout),
                    ctx.cancelled)
    if out.name != "complete":
        _release_if_mine(lift, e.name)
        return out
    return Outcome("complete", f"elevator {e.name} open at level {level}, holding its "
                               f"doors for {lift.me}")


def elevator_req(ctx: Context, p: ElevatorReqAction) -> Outcome:
    """``elevator_req_action``: the car at ``level``, its doors open for this robot."""
    got = _car(ctx, p.elevator_name, p.level)
    if isinstance(got, Outcome):
        return got
    lift, e = got
    out = _call(ctx, lift, e, p.level, p.timeout)
    if out.name == "complete" and p.direction:
        return Outcome("complete", f"{out.reason} (going {p.direction})")
    return out


def lbt_elevator_req(ctx: Context, p: LbtElevatorReqAction) -> Outcome:
    """``lbt_elevator_req_action``: ``enter`` (the car open at ``from_level``) or ``leave``
    (the car open at ``to_level``), its doors held until ``lbt_elevator_ack_action``."""
    got = _car(ctx, p.elevator_name, p.from_level, p.to_level)
    if isinstance(got, Outcome):
        return got
    lift, e = got
    pending, lift.lbt = lift.lbt, None
    if p.cmd == "enter":
        out = _call(ctx, lift, e, p.from_level, p.timeout)
    elif pending is not None and pending.cmd == "enter" and pending.elevator == e.name:
        lift.lbt = pending
        out = Outcome("error", f"elevator {e.name} still waits at level {pending.from_level} "
                               "for this robot to enter: send lbt_elevator_ack_action once "
                               "inside")
    else:
        out = _leave(ctx, lift, e, p)
    if out.name == "complete":
        lift.lbt = LbtRequest(p.cmd, e.name, p.from_level, p.to_level)
    return out


def _leave(ctx: Context, lift: ElevatorLink, e: Elevator, p: LbtElevatorReqAction) -> Outcome:
    s = lift.state(e.name)
    if s is None or s.holder != lift.me:
        return Outcome("error", f"this robot does not hold elevator {e.name} (holder: "
                                f"{(s.holder if s else '') or 'none'}): send "
                                "lbt_elevator_req_action cmd enter and its ack first")
    out = lift.wait(e.name, _open_for(lift.me, p.to_level, "WAITING_OUT"),
                    f"elevator {e.name} open at level {p.to_level}",
                    _deadline(ctx, p.timeout), ctx.cancelled)
    if out.name != "complete":
        _release_if_mine(lift, e.name)
        return out
    where = _follow_the_car(ctx, lift, e, p.from_level, p.to_level)
    if where.name != "complete":
        return where
    return Outcome("complete", f"elevator {e.name} open at level {p.to_level}, holding its "
                               f"doors for {lift.me}; {where.reason}")


def _follow_the_car(ctx: Context, lift: ElevatorLink, e: Elevator, here: int,
                    there: int) -> Outcome:
    """Nav on ``there``'s floor map, relocalised at the robot's place in the car (as a
    ride's). A robot whose pose is unknown or not in the car keeps its map."""
    pose = ctx.robot.pose()
    if pose is None:
        return Outcome("complete", "the robot's pose is unknown: nav's map unchanged")
    if not e.inside(here, pose[0], pose[1]):
        return Outcome("complete", "the robot is not in the car on nav's map: nav's map "
                                   "unchanged")
    floor = lift.building.floor(there).map_name
    moved = ctx.robot.switch_map(floor, "", -1)
    if moved.name != "complete":
        return Outcome("error", f"at level {there}: {moved.reason}")
    p = e.car_pose(there) * (e.car_pose(here).inverse() * Pose2(*pose))
    moved = ctx.robot.relocalise(p.x, p.y, p.theta)
    if moved.name != "complete":
        return Outcome("error", f"at level {there}: {moved.reason}")
    return Outcome("complete", f"nav on map {floor}, in the car")


def lbt_elevator_ack(ctx: Context, p: LbtElevatorAckAction) -> Outcome:
    """``lbt_elevator_ack_action``: after ``enter``, ``go`` to the request's ``to_level``;
    after ``leave``, ``release``."""
    lift = ctx.robot.elevators
    req = lift.lbt if lift is not None else None
    if lift is None or req is None:
        return Outcome("error", "nothing to acknowledge: no lbt_elevator_req_action "
                                "completed before this ack")
    if req.cmd == "enter":
        out = lift.command(req.elevator, "go", req.to_level)
    else:
        out = lift.command(req.elevator, "release")
    if out.name == "complete":
        lift.lbt = None
    return out
