"""Hierarchical state machines after ROS executive_smach.

States declare outcomes and userdata keys; containers (`StateMachine`, `Sequence`,
`Concurrence`, `Iterator`) are states, nest, and check their wiring before anything
runs. The core imports no middleware; the ROS-aware states (`MonitorState`,
`ServiceState`, `SimpleActionState`) and the `IntrospectionServer` use a `zenros.Node`
and are imported on first use. See docs/smach.md.
"""

from typing import TYPE_CHECKING, Any

from ..errors import (
    InvalidStateError,
    InvalidTransitionError,
    InvalidUserCodeError,
    SmachError,
    UserDataError,
)
from .concurrence import ChildOutcomes, Concurrence
from .condition import ConditionState
from .container import Container
from .execution import Execution
from .introspection import (
    ContainerEvent,
    ContainerStatus,
    Listener,
    SetInitialState,
    SetInitialStateRequest,
    SetInitialStateResponse,
    StateStructure,
    TransitionInfo,
)
from .iterator import Iterator
from .sequence import Sequence
from .state import CBState, State, cb_interface
from .state_machine import StateMachine
from .userdata import Remapper, UserData, UserDataAccess

if TYPE_CHECKING:
    from .action_state import SimpleActionState
    from .introspection_server import IntrospectionServer
    from .monitor import MonitorState
    from .service_state import ServiceState

_LAZY = {
    "IntrospectionServer": "introspection_server",
    "MonitorState": "monitor",
    "ServiceState": "service_state",
    "SimpleActionState": "action_state",
}


def __getattr__(name: str) -> Any:
    """Import the Zenoh-backed parts on first use, so the core stays middleware-free."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    return getattr(importlib.import_module(f"{__name__}.{module}"), name)


__all__ = [
    "CBState",
    "ChildOutcomes",
    "Concurrence",
    "ConditionState",
    "Container",
    "ContainerEvent",
    "ContainerStatus",
    "Execution",
    "IntrospectionServer",
    "InvalidStateError",
    "InvalidTransitionError",
    "InvalidUserCodeError",
    "Iterator",
    "Listener",
    "MonitorState",
    "Remapper",
    "Sequence",
    "ServiceState",
    "SetInitialState",
    "SetInitialStateRequest",
    "SetInitialStateResponse",
    "SimpleActionState",
    "SmachError",
    "State",
    "StateMachine",
    "StateStructure",
    "TransitionInfo",
    "UserData",
    "UserDataAccess",
    "UserDataError",
    "cb_interface",
]
