"""lifecycle_msgs: the states, transitions and services of ROS 2's managed nodes.

ROS 2's definitions (lifecycle_msgs 2.3.0) with their constants as class attributes, as the
generated ROS classes have them; `zenros.lifecycle` speaks them.
"""

from __future__ import annotations

import msgspec

from ..message import Message, define_service

__all__ = [
    "ChangeState",
    "ChangeStateRequest",
    "ChangeStateResponse",
    "GetAvailableStates",
    "GetAvailableStatesRequest",
    "GetAvailableStatesResponse",
    "GetAvailableTransitions",
    "GetAvailableTransitionsRequest",
    "GetAvailableTransitionsResponse",
    "GetState",
    "GetStateRequest",
    "GetStateResponse",
    "State",
    "Transition",
    "TransitionDescription",
    "TransitionEvent",
]


class State(Message):
    """A primary state (0-4) or a transition state (10-15) of the lifecycle."""

    __msgtype__ = "lifecycle_msgs/State"
    id: int = 0
    label: str = ""

    PRIMARY_STATE_UNKNOWN = 0
    PRIMARY_STATE_UNCONFIGURED = 1
    PRIMARY_STATE_INACTIVE = 2
    PRIMARY_STATE_ACTIVE = 3
    PRIMARY_STATE_FINALIZED = 4
    TRANSITION_STATE_CONFIGURING = 10
    TRANSITION_STATE_CLEANINGUP = 11
    TRANSITION_STATE_SHUTTINGDOWN = 12
    TRANSITION_STATE_ACTIVATING = 13
    TRANSITION_STATE_DEACTIVATING = 14
    TRANSITION_STATE_ERRORPROCESSING = 15


class Transition(Message):
    """A transition, by id and label (a request names one of them; the label wins)."""

    __msgtype__ = "lifecycle_msgs/Transition"
    id: int = 0
    label: str = ""

    TRANSITION_CREATE = 0
    TRANSITION_CONFIGURE = 1
    TRANSITION_CLEANUP = 2
    TRANSITION_ACTIVATE = 3
    TRANSITION_DEACTIVATE = 4
    TRANSITION_UNCONFIGURED_SHUTDOWN = 5
    TRANSITION_INACTIVE_SHUTDOWN = 6
    TRANSITION_ACTIVE_SHUTDOWN = 7
    TRANSITION_DESTROY = 8
    TRANSITION_ON_CONFIGURE_SUCCESS = 10
    TRANSITION_ON_CONFIGURE_FAILURE = 11
    TRANSITION_ON_CONFIGURE_ERROR = 12
    TRANSITION_ON_CLEANUP_SUCCESS = 20
    TRANSITION_ON_CLEANUP_FAILURE = 21
    TRANSITION_ON_CLEANUP_ERROR = 22
    TRANSITION_ON_ACTIVATE_SUCCESS = 30
    TRANSITION_ON_ACTIVATE_FAILURE = 31
    TRANSITION_ON_ACTIVATE_ERROR = 32
    TRANSITION_ON_DEACTIVATE_SUCCESS = 40
    TRANSITION_ON_DEACTIVATE_FAILURE = 41
    TRANSITION_ON_DEACTIVATE_ERROR = 42
    TRANSITION_ON_SHUTDOWN_SUCCESS = 50
    TRANSITION_ON_SHUTDOWN_FAILURE = 51
    TRANSITION_ON_SHUTDOWN_ERROR = 52
    TRANSITION_ON_ERROR_SUCCESS = 60
    TRANSITION_ON_ERROR_FAILURE = 61
    TRANSITION_ON_ERROR_ERROR = 62
    TRANSITION_CALLBACK_SUCCESS = 97
    TRANSITION_CALLBACK_FAILURE = 98
    TRANSITION_CALLBACK_ERROR = 99


class TransitionDescription(Message):
    __msgtype__ = "lifecycle_msgs/TransitionDescription"
    transition: Transition = msgspec.field(default_factory=Transition)
    start_state: State = msgspec.field(default_factory=State)
    goal_state: State = msgspec.field(default_factory=State)


class TransitionEvent(Message):
    """One step of the state machine, published on a node's ``~/transition_event``."""

    __msgtype__ = "lifecycle_msgs/TransitionEvent"
    timestamp: int = 0
    transition: Transition = msgspec.field(default_factory=Transition)
    start_state: State = msgspec.field(default_factory=State)
    goal_state: State = msgspec.field(default_factory=State)


class ChangeStateRequest(Message):
    __msgtype__ = "lifecycle_msgs/ChangeStateRequest"
    transition: Transition = msgspec.field(default_factory=Transition)


class ChangeStateResponse(Message):
    __msgtype__ = "lifecycle_msgs/ChangeStateResponse"
    success: bool = False


class GetStateRequest(Message):
    __msgtype__ = "lifecycle_msgs/GetStateRequest"


class GetStateResponse(Message):
    __msgtype__ = "lifecycle_msgs/GetStateResponse"
    current_state: State = msgspec.field(default_factory=State)


class GetAvailableStatesRequest(Message):
    __msgtype__ = "lifecycle_msgs/GetAvailableStatesRequest"


class GetAvailableStatesResponse(Message):
    __msgtype__ = "lifecycle_msgs/GetAvailableStatesResponse"
    available_states: list[State] = msgspec.field(default_factory=list)


class GetAvailableTransitionsRequest(Message):
    __msgtype__ = "lifecycle_msgs/GetAvailableTransitionsRequest"


class GetAvailableTransitionsResponse(Message):
    __msgtype__ = "lifecycle_msgs/GetAvailableTransitionsResponse"
    available_transitions: list[TransitionDescription] = msgspec.field(default_factory=list)


ChangeState = define_service("lifecycle_msgs/ChangeState", ChangeStateRequest,
                             ChangeStateResponse)
GetState = define_service("lifecycle_msgs/GetState", GetStateRequest, GetStateResponse)
GetAvailableStates = define_service("lifecycle_msgs/GetAvailableStates",
                                    GetAvailableStatesRequest, GetAvailableStatesResponse)
GetAvailableTransitions = define_service("lifecycle_msgs/GetAvailableTransitions",
                                         GetAvailableTransitionsRequest,
                                         GetAvailableTransitionsResponse)
