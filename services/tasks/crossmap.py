"""Cross-map navigation: a ``nav_action`` whose ``map`` is not the current map (docs/robot-api.md
§6.4, §6.7).

The route comes from `zenros.maps.maproute.find_route` over the point connections. For each
hop the robot drives to the connection's point on the current map, nav switches to the next map,
and the robot is relocalised at the connected point (keeping how far it stopped from the
point on the old map), then it carries on; the last leg goes to the goal itself. An elevator
connection is ridden (`elevator_ride.ride`) when the tasks service knows the building
(``building:=PATH``); without one a route that needs an elevator ends in ERROR naming the
connection before the robot moves. ``timeout`` bounds the whole trip.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import msgspec
from zenros.building import elevator_of_path
from zenros.maps.maproute import Hop, NoRoute, find_route
from zenros.msgs.zenros_msgs.task_actions import NavAction
from zenros.se2 import wrap_angle

from .elevator_link import ElevatorLink
from .elevator_ride import ride
from .robot import Outcome, Robot

__all__ = ["carry_over", "navigate_across"]

Pose = tuple[float, float, float]
Leg = Callable[[NavAction], Outcome]


def carry_over(leave: Pose, enter: Pose, robot: Pose | None) -> Pose:
    """Where the robot is on the new map: ``enter`` composed with the robot's offset from
    ``leave`` on the old map (``enter`` itself when the robot's pose is not known)."""
    if robot is None:
        return enter
    dx, dy = robot[0] - leave[0], robot[1] - leave[1]
    c, s = math.cos(leave[2]), math.sin(leave[2])
    lx, ly = c * dx + s * dy, -s * dx + c * dy  # the offset in leave's frame
    c2, s2 = math.cos(enter[2]), math.sin(enter[2])
    theta = wrap_angle(enter[2] + (robot[2] - leave[2]))
    return enter[0] + c2 * lx - s2 * ly, enter[1] + s2 * lx + c2 * ly, theta


def navigate_across(robot: Robot, params: NavAction, current: str, leg: Leg,
                    note: Callable[[str], None], lift: ElevatorLink | None = None,
                    cancelled: Callable[[], bool] = lambda: False) -> Outcome:
    """Take ``params`` (a nav_action on map ``params.map``) from map ``current``.

    ``leg(action)`` navigates within the current map (a same-map nav_action); ``note``
    records progress text (which map, which connection) on the action. ``lift``: the
    building's elevators, to ride an elevator connection.
    """
    target = params.map
    try:
        route = find_route(robot.point_connections(), current, target)
    except (NoRoute, LookupError) as exc:
        return Outcome("error", str(exc))
    for hop in route:
        if hop.type == "elevator":
            why = _rideable(lift, hop)
            if why:
                return Outcome("error", f"the route from map {current!r} to map {target!r} "
                                        f"needs the {hop.describe()}: {why}")
        elif hop.type != "direct":
            return Outcome("error", f"unknown connection type in {hop.describe()}")
    try:
        if isinstance(params.index, int):  # the goal point must exist before it sets off
            robot.nav_point(params.index, target, params.path)
        ends = [(robot.nav_point(h.leave.point_index, h.leave.map, h.leave.path),
                 robot.nav_point(h.enter.point_index, h.enter.map, h.enter.path))
                for h in route]
    except LookupError as exc:
        return Outcome("error", f"route to map {target!r}: {exc}")
    timeout = params.timeout
    end = robot.now() + timeout if timeout > 0 else None

    def left() -> float | None:
        return None if end is None else end - robot.now()

    for hop, (leave, enter) in zip(route, ends, strict=True):
        out = _leg(leg, NavAction(x=leave[0], y=leave[1], theta=leave[2]), left(), timeout)
        if out.name != "complete":
            return Outcome(out.name, f"on the way to {hop.describe()}: {out.reason}")
        if hop.type == "elevator" and lift is not None:
            out = ride(robot, lift, elevator_of_path(hop.leave.path) or "", hop,
                       lambda a: _leg(leg, a, left(), timeout), note,
                       lambda: end is not None and robot.now() > end, cancelled)
        else:
            out = _cross(robot, hop, leave, enter)
        if out.name != "complete":
            return out
        note(f"on map {hop.enter.map} via {hop.describe()}")
    return _leg(leg, params, left(), timeout)


def _rideable(lift: ElevatorLink | None, hop: Hop) -> str:
    """"" when ``hop`` (an elevator connection) can be ridden, else why not."""
    if lift is None:
        return "the tasks service knows no building (building:=PATH) to ride its elevator"
    name = elevator_of_path(hop.leave.path)
    if name is None or elevator_of_path(hop.enter.path) != name:
        return (f"its points are not the hall points of one elevator (paths "
                f"{hop.leave.path!r}, {hop.enter.path!r})")
    try:
        lift.building.elevator(name)
        lift.building.level_of_map(hop.leave.map)
        lift.building.level_of_map(hop.enter.map)
    except LookupError as exc:
        return str(exc)
    return ""


def _leg(leg: Leg, params: NavAction, remaining: float | None, timeout: float) -> Outcome:
    if remaining is not None and remaining <= 0:
        return Outcome("error", f"not done within {timeout:g} s")
    return leg(msgspec.structs.replace(params, timeout=0.0 if remaining is None else remaining))


def _cross(robot: Robot, hop: Hop, leave: Pose, enter: Pose) -> Outcome:
    here = robot.pose()
    out = robot.switch_map(hop.enter.map, hop.enter.path, -1)
    if out.name != "complete":
        return Outcome("error", f"at {hop.describe()}: {out.reason}")
    out = robot.relocalise(*carry_over(leave, enter, here))
    if out.name != "complete":
        return Outcome("error", f"at {hop.describe()}: {out.reason}")
    return Outcome("complete")
