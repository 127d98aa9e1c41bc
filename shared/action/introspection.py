"""Action introspection, as ROS 2 Kilted has it (`configure_introspection` on an action
server): the server publishes an event for each request it receives and each response it
sends on its three services, ``<action>/_action/send_goal``, ``cancel_goal`` and
``get_result``, each on ``<service>/_service_event`` as service introspection does
(`zenros.service_events`: OFF, METADATA, CONTENTS). ``zenros action echo`` shows them, with
the action's feedback and status."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Any

from ..message import ActionType, ServiceType
from ..qos import QoSProfile
from ..service_events import ServiceEvents, ServiceIntrospectionState
from .types import CancelGoal
from .wire import wire_types

if TYPE_CHECKING:
    from ..context import Context

__all__ = ["PARTS", "ActionEvents", "action_service_types"]

PARTS = ("send_goal", "cancel_goal", "get_result")


@cache
def action_service_types(action: ActionType[Any, Any, Any]) -> dict[str, ServiceType[Any, Any]]:
    """The three services of an action as service types (``pkg/Name_SendGoal``, ...)."""
    wire = wire_types(action)
    return {
        "send_goal": ServiceType(f"{action.name}_SendGoal", wire.SendGoalRequest,
                                 wire.SendGoalResponse),
        "cancel_goal": CancelGoal,
        "get_result": ServiceType(f"{action.name}_GetResult", wire.GetResultRequest,
                                  wire.GetResultResponse),
    }


def part_name(action_name: str, part: str) -> str:
    """The ROS 2 name of one of an action's services: ``/fib/_action/send_goal``."""
    return f"{action_name}/_action/{part}"


@dataclass
class ActionEvents:
    """The events of one action server's three services; `on` is False until configured."""

    send_goal: ServiceEvents
    cancel_goal: ServiceEvents
    get_result: ServiceEvents

    @classmethod
    def of(cls, ctx: Context, node: str, action: ActionType[Any, Any, Any],
           name: str) -> ActionEvents:
        types = action_service_types(action)
        made = {p: ServiceEvents(ctx, node, types[p], part_name(name, p), client=False)
                for p in PARTS}
        return cls(**made)

    @property
    def on(self) -> bool:
        return self.send_goal.state is not ServiceIntrospectionState.OFF

    def configure(self, clock: Any, qos: QoSProfile | None,
                  state: ServiceIntrospectionState) -> None:
        for events in (self.send_goal, self.cancel_goal, self.get_result):
            events.configure(clock, qos, state)

    def close(self) -> None:
        for events in (self.send_goal, self.cancel_goal, self.get_result):
            events.close()
