"""Hierarchical state machines after ROS executive_smach, with no middleware import.

States declare outcomes and userdata keys; containers (`StateMachine`, `Sequence`,
`Concurrence`, `Iterator`) are states, nest, and check their wiring before anything
runs. See docs/smach.md.
"""

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
    StateStructure,
    TransitionInfo,
)
from .iterator import Iterator
from .sequence import Sequence
from .state import CBState, State, cb_interface
from .state_machine import StateMachine
from .userdata import Remapper, UserData, UserDataAccess

__all__ = [
    "CBState",
    "ChildOutcomes",
    "Concurrence",
    "ConditionState",
    "Container",
    "ContainerEvent",
    "ContainerStatus",
    "Execution",
    "InvalidStateError",
    "InvalidTransitionError",
    "InvalidUserCodeError",
    "Iterator",
    "Listener",
    "Remapper",
    "Sequence",
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
