"""rcl_interfaces: Log, the payload of /rosout; ParameterEvent, the payload of
/parameter_events, with Parameter, ParameterValue and ParameterType (ROS 2's definitions)."""

from __future__ import annotations

from typing import Annotated, ClassVar

import msgspec

from ..message import Message
from .builtin_interfaces import Time


class Log(Message):
    """One log record (ROS 2 layout); levels DEBUG=10, INFO=20, WARN=30, ERROR=40, FATAL=50."""

    __msgtype__ = "rcl_interfaces/Log"
    stamp: Time = msgspec.field(default_factory=Time)
    level: int = 20
    name: str = ""
    msg: str = ""
    file: str = ""
    function: str = ""
    line: int = 0

    DEBUG = 10
    INFO = 20
    WARN = 30
    ERROR = 40
    FATAL = 50


Byte = Annotated[int, msgspec.Meta(ge=0, le=255)]


class ParameterType(Message):
    """The ``type`` of a `ParameterValue` (constants only, as in ROS 2)."""

    __msgtype__ = "rcl_interfaces/ParameterType"
    PARAMETER_NOT_SET: ClassVar[int] = 0
    PARAMETER_BOOL: ClassVar[int] = 1
    PARAMETER_INTEGER: ClassVar[int] = 2
    PARAMETER_DOUBLE: ClassVar[int] = 3
    PARAMETER_STRING: ClassVar[int] = 4
    PARAMETER_BYTE_ARRAY: ClassVar[int] = 5
    PARAMETER_BOOL_ARRAY: ClassVar[int] = 6
    PARAMETER_INTEGER_ARRAY: ClassVar[int] = 7
    PARAMETER_DOUBLE_ARRAY: ClassVar[int] = 8
    PARAMETER_STRING_ARRAY: ClassVar[int] = 9


class ParameterValue(Message):
    """One value; ``type`` (a `ParameterType` constant) says which field holds it."""

    __msgtype__ = "rcl_interfaces/ParameterValue"
    type: Byte = 0
    bool_value: bool = False
    integer_value: int = 0
    double_value: float = 0.0
    string_value: str = ""
    byte_array_value: list[Byte] = msgspec.field(default_factory=list)  # as UUID's
    bool_array_value: list[bool] = msgspec.field(default_factory=list)
    integer_array_value: list[int] = msgspec.field(default_factory=list)
    double_array_value: list[float] = msgspec.field(default_factory=list)
    string_array_value: list[str] = msgspec.field(default_factory=list)


class Parameter(Message):
    __msgtype__ = "rcl_interfaces/Parameter"
    name: str = ""
    value: ParameterValue = msgspec.field(default_factory=ParameterValue)


class ParameterEvent(Message):
    """What changed in one node's parameters: declared (new), set (changed), undeclared."""

    __msgtype__ = "rcl_interfaces/ParameterEvent"
    stamp: Time = msgspec.field(default_factory=Time)
    node: str = ""
    new_parameters: list[Parameter] = msgspec.field(default_factory=list)
    changed_parameters: list[Parameter] = msgspec.field(default_factory=list)
    deleted_parameters: list[Parameter] = msgspec.field(default_factory=list)
