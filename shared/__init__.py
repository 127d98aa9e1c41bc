"""zenros: a ROS-like robot runtime on Eclipse Zenoh."""

from .clock import Duration, ManualClock, Rate, SteadyClock, SystemClock, Time
from .context import Context
from .errors import (
    ConfigError,
    DecodeError,
    EncodeError,
    GoalRejectedError,
    InvalidNameError,
    InvalidParameterValueError,
    ParameterError,
    ParameterNotDeclaredError,
    ServiceError,
    ServiceUnavailableError,
    TypeMismatchError,
    ZenrosError,
    ZenrosTimeout,
)
from .executor import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from .message import ActionType, Message, ServiceType, define_action, define_service
from .node import Node
from .qos import QOS_DEFAULT, QOS_LATCHED, QOS_SENSOR, Durability, QoSProfile, Reliability
from .runtime import run
from .session import SessionOptions

__all__ = [
    "QOS_DEFAULT",
    "QOS_LATCHED",
    "QOS_SENSOR",
    "ActionType",
    "ConfigError",
    "Context",
    "DecodeError",
    "Durability",
    "Duration",
    "EncodeError",
    "GoalRejectedError",
    "InvalidNameError",
    "InvalidParameterValueError",
    "ManualClock",
    "Message",
    "MutuallyExclusiveCallbackGroup",
    "Node",
    "ParameterError",
    "ParameterNotDeclaredError",
    "QoSProfile",
    "Rate",
    "ReentrantCallbackGroup",
    "Reliability",
    "ServiceError",
    "ServiceType",
    "ServiceUnavailableError",
    "SessionOptions",
    "SteadyClock",
    "SystemClock",
    "Time",
    "TypeMismatchError",
    "ZenrosError",
    "ZenrosTimeout",
    "define_action",
    "define_service",
    "run",
]
