"""A ride in the building's elevator: the ``elevator`` hop of a cross-map route
(docs/building.md, "Going to another floor").

At the hall point of the current floor: call the car, wait for it to stand open here for this
robot (``WAITING_IN``), drive into the car (facing the doors), send it to the other floor, wait
for it to stand open there (``WAITING_OUT``), switch nav to that floor's map and relocalise at
the same place in the car, drive out to the hall point (and fix the estimate on the floor's
reflectors there, where the map has landmarks), and release the car. Each stage is
written in the action's ``result`` text. A cancel or a failure releases the car: its doors
never close on the robot (the controller's light curtain), so the robot is never caught
between them; a robot that stopped inside stays there, safe, until it is sent out.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from zenros.building import Elevator
from zenros.maps.maproute import Hop
from zenros.msgs.zenros_msgs import ElevatorState
from zenros.msgs.zenros_msgs.task_actions import NavAction
from zenros.se2 import Pose2, wrap_angle

from .elevator_link import ElevatorLink
from .robot import Outcome, Robot

__all__ = ["ride"]

OPEN = 0.999  # the car's doors count as open from here
AT_FLOOR = 0.01


def ride(robot: Robot, lift: ElevatorLink, elevator: str, hop: Hop,
         leg: Callable[[NavAction], Outcome], note: Callable[[str], None],
         time_up: Callable[[], bool], cancelled: Callable[[], bool]) -> Outcome:
    """Ride car ``elevator`` from ``hop.leave``'s floor to ``hop.enter``'s; the robot stands
    at the hall point of ``hop.leave`` already."""
    b = lift.building
    try:
        e = b.elevator(elevator)
        here, there = b.level_of_map(hop.leave.map), b.level_of_map(hop.enter.map)
    except LookupError as exc:
        return Outcome("error", f"at {hop.describe()}: {exc}")
    if here not in e.levels or there not in e.levels:
        return Outcome("error", f"elevator {e.name} does not serve levels {here} and {there}")
    held = lift.state(e.name)
    if held is None or held.holder != lift.me or held.level != here \
            or held.state != "WAITING_IN":  # not called here already (elevator_req_action)
        note(f"calling elevator {e.name} to level {here}")
        out = lift.command(e.name, "call", here)
        if out.name != "complete":
            return out
    out = _ride(robot, lift, e, here, there, leg, note, time_up, cancelled)
    released = lift.command(e.name, "release")
    if out.name == "complete" and released.name != "complete":
        return released
    if out.name == "complete":
        note(f"on level {there} (map {hop.enter.map}) by elevator {e.name}")
    return out


def _ride(robot: Robot, lift: ElevatorLink, e: Elevator, here: int, there: int,
          leg: Callable[[NavAction], Outcome], note: Callable[[str], None],
          time_up: Callable[[], bool], cancelled: Callable[[], bool]) -> Outcome:
    me = lift.me

    def open_for_me(level: int, state: str) -> Callable[[ElevatorState], bool]:
        return lambda s: (s.holder == me and s.state == state and s.level == level
                          and abs(s.position - level) < AT_FLOOR and s.door >= OPEN)

    note(f"waiting for elevator {e.name} at level {here}")
    out = lift.wait(e.name, open_for_me(here, "WAITING_IN"),
                    f"elevator {e.name} open at level {here}", time_up, cancelled)
    if out.name != "complete":
        return out
    note(f"entering elevator {e.name} at level {here}")
    car = e.car_pose(here)
    out = leg(NavAction(x=car.x, y=car.y, theta=car.theta))
    if out.name != "complete":
        return Outcome(out.name, f"entering elevator {e.name}: {out.reason}")
    pose = robot.pose()
    if pose is None or not e.inside(here, pose[0], pose[1]):
        return Outcome("error", f"not inside elevator {e.name} after driving in")
    note(f"riding elevator {e.name} to level {there}")
    out = lift.command(e.name, "go", there)
    if out.name != "complete":
        return out
    out = lift.wait(e.name, open_for_me(there, "WAITING_OUT"),
                    f"elevator {e.name} open at level {there}", time_up, cancelled)
    if out.name == "preempted":
        # the car is on its way with the robot aboard: it arrives whatever the task does,
        # and nav must know the floor it is on then (the car waits open for it there)
        limit = robot.now() + _most(e, here, there)
        arrived = lift.wait(e.name, lambda s: s.level == there and s.door >= OPEN,
                            f"elevator {e.name} at level {there}",
                            lambda: robot.now() > limit, lambda: False)
        if arrived.name != "complete":
            return Outcome("error", f"cancelled during the ride, and {arrived.reason}")
    elif out.name != "complete":
        return out
    floor = lift.building.floor(there).map_name
    moved = robot.switch_map(floor, "", -1)
    if moved.name != "complete":
        return Outcome("error", f"arrived at level {there}: {moved.reason}")
    moved = robot.relocalise(*_in_car(e, here, there, pose))
    if moved.name != "complete":
        return Outcome("error", f"arrived at level {there}: {moved.reason}")
    if out.name == "preempted":
        return Outcome("preempted", f"cancelled during the ride: in elevator {e.name} at "
                                    f"level {there}, on map {floor}")
    note(f"leaving elevator {e.name} at level {there}")
    hall = e.hall_pose(there)
    out = leg(NavAction(x=hall.x, y=hall.y, theta=wrap_angle(hall.theta + math.pi)))
    if out.name != "complete":
        return Outcome(out.name, f"leaving elevator {e.name}: {out.reason}")
    fix = robot.relocalise_landmarks()  # the carried pose stands when no reflector helps
    note(f"out of elevator {e.name} at level {there}: {fix.reason}")
    return Outcome("complete")


def _most(e: Elevator, here: int, there: int) -> float:
    """Seconds the car may take at most to finish a ride from ``here`` to ``there`` (its
    doors, the floors between, and room for a slow box)."""
    return 3.0 * (2 * e.door_s + abs(there - here) * e.travel_s) + 10.0


def _in_car(e: Elevator, here: int, there: int,
            pose: tuple[float, float, float]) -> tuple[float, float, float]:
    """``pose`` (in the car at ``here``) at the same place in the car at ``there``."""
    p = e.car_pose(there) * (e.car_pose(here).inverse() * Pose2(*pose))
    return p.x, p.y, p.theta
