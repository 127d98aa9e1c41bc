"""The building's elevators (docs/building.md; docs/robot-api.md §6.11).

One elevator controller runs per building (``python -m zenros.services.elevator``) and owns
every car; its keys are absolute, outside any robot's namespace, so every robot of a fleet
shares them:

- ``/building/elevators/<name>/state``: ``zenros_msgs/ElevatorState``, latched, on every
  change and at 2 Hz.
- ``/building/elevators/<name>/command``: ``zenros_msgs/ElevatorCommand``.
- ``/building/bodies``: ``zenros_msgs/BuildingBody``, published by each simulated chassis of
  a building (its floor and true pose, 10 Hz while near a car): the controller's light
  curtain and rider count (doors never close on a body in the doorway).
"""

from __future__ import annotations

from typing import Literal

import msgspec

from ...message import Message, define_service
from ..std_msgs import Header

__all__ = [
    "BuildingBody",
    "ElevatorCommand",
    "ElevatorCommandRequest",
    "ElevatorCommandResponse",
    "ElevatorState",
]


class ElevatorState(Message):
    """A car as its controller sees it.

    ``level``: the floor the car is at, or last passed while moving; ``position``: where the
    car is in floors (1.5 half way from 1 to 2). ``direction``: ``UP``, ``DOWN`` or ``STOP``
    (the robot API spells DOWN ``DONW``; the gateway answers in its spelling). ``state``:
    ``WAITING_IN`` (at ``holder``'s call floor, doors open, waiting for it to enter),
    ``WAITING_OUT`` (at ``holder``'s destination, doors open, waiting for it to leave) or
    ``NONE``. ``door``: 0 closed .. 1 open (the front doors; a car has no back doors here).
    ``calls``: levels asked for, in the order they will be served. ``holder``: the robot the
    car serves now ("" when free); ``queue``: robots waiting for it, first first.
    ``riders``: robots whose body is inside the car.
    """

    __msgtype__ = "zenros_msgs/ElevatorState"
    header: Header = msgspec.field(default_factory=Header)
    name: str = ""
    level: int = 0
    position: float = 0.0
    direction: Literal["UP", "DOWN", "STOP"] = "STOP"
    state: Literal["NONE", "WAITING_IN", "WAITING_OUT"] = "NONE"
    door: float = 0.0
    front_door_open: bool = False
    back_door_open: bool = False
    levels: list[int] = msgspec.field(default_factory=list)
    calls: list[int] = msgspec.field(default_factory=list)
    holder: str = ""
    queue: list[str] = msgspec.field(default_factory=list)
    riders: list[str] = msgspec.field(default_factory=list)
    capacity: int = 1


class ElevatorCommandRequest(Message):
    """``command``:

    - ``call``: ``robot`` wants the car at ``level`` (queued behind the holder, if any);
      when its turn comes the car goes there, opens and waits (``WAITING_IN``) ``hold_s``.
    - ``go``: the holder, inside, sends the car to ``level``; it closes (once the doorway is
      clear), rides, opens there (``WAITING_OUT``).
    - ``release``: ``robot`` is done (out of the car) or gives up its call or claim.
    - ``to_level``: the robot API's ``elevator_to_level``: call the car to ``level`` with no
      robot (a person's call).
    - ``open`` / ``close``: the door buttons (``close`` waits for a clear doorway).
    """

    __msgtype__ = "zenros_msgs/ElevatorCommandRequest"
    command: Literal["call", "go", "release", "to_level", "open", "close"] = "call"
    robot: str = ""
    level: int = 0


class ElevatorCommandResponse(Message):
    """``success`` false with the reason in ``message``."""

    __msgtype__ = "zenros_msgs/ElevatorCommandResponse"
    success: bool = False
    message: str = ""


ElevatorCommand = define_service("zenros_msgs/ElevatorCommand", ElevatorCommandRequest,
                                 ElevatorCommandResponse)


class BuildingBody(Message):
    """A simulated robot's body in the building: ``robot`` (its namespace, "/" for one
    robot), the ``level`` it is on, its true pose on that floor's map and its radius."""

    __msgtype__ = "zenros_msgs/BuildingBody"
    header: Header = msgspec.field(default_factory=Header)
    robot: str = ""
    level: int = 0
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    radius: float = 0.2
