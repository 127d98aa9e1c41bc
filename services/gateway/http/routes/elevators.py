"""REST ``/navigation/get_elevator_info``, ``elevator_to_level``, ``elevator_open_door``
(docs/robot-api.md §6.11): the building's elevator controller (`ports.elevator_link`).

No controller in the graph (the robot was launched without ``building:=``): 503; an elevator
the building does not have: 404; a command the controller refuses (a level it does not serve,
the doors held by a robot): 400 with its reason.
"""

from __future__ import annotations

from typing import Annotated, Literal

import msgspec
from zenros.msgs.zenros_msgs.elevator import ElevatorCommandRequest

from ...ports.elevator_link import NO_CONTROLLER, ElevatorLink
from ..api import Answer, Api, ApiError, Call
from ..context import Context

__all__ = ["add_elevator_routes"]

ElevatorName = Annotated[str, msgspec.Meta(max_length=64)]
Level = Annotated[int, msgspec.Meta(ge=-1000, le=1000)]
_SPELLING = {"UP": "UP", "DOWN": "DONW", "STOP": "STOP"}  # the API spells DOWN "DONW"


class InfoQuery(msgspec.Struct, forbid_unknown_fields=True):
    elevator_name: ElevatorName = ""


class LevelQuery(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    elevator_name: ElevatorName = ""
    level: Level


class DoorQuery(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    elevator_name: ElevatorName = ""
    open: Literal[0, 1]


def _link(ctx: Context) -> ElevatorLink:
    link = ctx.elevators
    if link is None:
        raise ApiError(503, NO_CONTROLLER)
    return link


async def get_elevator_info(call: Call[None, InfoQuery]) -> Answer:
    """The elevator's floor, direction (``UP``, ``DONW``, ``STOP``), state (``NONE``,
    ``WAITING_IN``, ``WAITING_OUT``) and doors (``elevator_name``: default, the first)."""
    s = await _link(call.ctx).state(call.query.elevator_name)
    return {"level": s.level, "direction": _SPELLING[s.direction], "state": s.state,
            "front_door_open": s.front_door_open, "back_door_open": s.back_door_open,
            "name": s.name}


async def elevator_to_level(call: Call[None, LevelQuery]) -> Answer:
    """Call the elevator to ``level`` (a person's call: it comes, opens, dwells)."""
    q = call.query
    await _link(call.ctx).command(q.elevator_name,
                              ElevatorCommandRequest(command="to_level", level=q.level))
    return {"result": True}


async def elevator_open_door(call: Call[None, DoorQuery]) -> Answer:
    """Open (``open=1``: at the floor it stands at, for its dwell) or close (``open=0``:
    once the doorway is clear) the elevator's doors."""
    q = call.query
    await _link(call.ctx).command(q.elevator_name, ElevatorCommandRequest(
        command="open" if q.open else "close"))
    return {"status": "ok"}


def add_elevator_routes(api: Api) -> None:
    """Route the §6.11 elevator operations."""
    api.add("GET", "/navigation/get_elevator_info", get_elevator_info)
    api.add("GET", "/navigation/elevator_to_level", elevator_to_level, result_style=True)
    api.add("GET", "/navigation/elevator_open_door", elevator_open_door)
