"""zenros: a ROS-like robot runtime on Eclipse Zenoh."""

import os as _os

# Before numpy is imported: a robot process does small matrix math, where OpenBLAS's pool of
# worker threads costs more than it gives (about 0.08 s of CPU at every interpreter start on
# a 2-core box, and threads that spin after each call). A value the user set is kept.
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

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
from .interfaces import path as _interface_path  # noqa: F401 (lookups read ZENROS_INTERFACE_PATH)
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
