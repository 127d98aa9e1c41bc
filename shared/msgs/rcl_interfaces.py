"""rcl_interfaces: Log, the payload of /rosout; ParameterEvent, the payload of
/parameter_events, with Parameter, ParameterValue and ParameterType; the parameter services
every node serves (ListParameters, DescribeParameters, GetParameterTypes, GetParameters,
SetParameters, SetParametersAtomically) with ParameterDescriptor and its ranges (ROS 2's
definitions)."""

from __future__ import annotations

from typing import Annotated, ClassVar

import msgspec

from ..message import Message, define_service
from ..primitives import UInt32
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


class FloatingPointRange(Message):
    __msgtype__ = "rcl_interfaces/FloatingPointRange"
    from_value: float = 0.0
    to_value: float = 0.0
    step: float = 0.0


class IntegerRange(Message):
    __msgtype__ = "rcl_interfaces/IntegerRange"
    from_value: int = 0
    to_value: int = 0
    step: int = 0  # uint64 on the wire (as lifecycle_msgs' timestamp)


class ParameterDescriptor(Message):
    __msgtype__ = "rcl_interfaces/ParameterDescriptor"
    name: str = ""
    type: Byte = 0
    description: str = ""
    additional_constraints: str = ""
    read_only: bool = False
    dynamic_typing: bool = False
    floating_point_range: Annotated[list[FloatingPointRange], msgspec.Meta(max_length=1)] = \
        msgspec.field(default_factory=list)
    integer_range: Annotated[list[IntegerRange], msgspec.Meta(max_length=1)] = \
        msgspec.field(default_factory=list)


class SetParametersResult(Message):
    __msgtype__ = "rcl_interfaces/SetParametersResult"
    successful: bool = False
    reason: str = ""


class ListParametersResult(Message):
    __msgtype__ = "rcl_interfaces/ListParametersResult"
    names: list[str] = msgspec.field(default_factory=list)
    prefixes: list[str] = msgspec.field(default_factory=list)


class ListParametersRequest(Message):
    __msgtype__ = "rcl_interfaces/ListParametersRequest"
    DEPTH_RECURSIVE: ClassVar[int] = 0
    prefixes: list[str] = msgspec.field(default_factory=list)
    depth: int = 0  # uint64 on the wire


class ListParametersResponse(Message):
    __msgtype__ = "rcl_interfaces/ListParametersResponse"
    result: ListParametersResult = msgspec.field(default_factory=ListParametersResult)


class DescribeParametersRequest(Message):
    __msgtype__ = "rcl_interfaces/DescribeParametersRequest"
    names: list[str] = msgspec.field(default_factory=list)


class DescribeParametersResponse(Message):
    __msgtype__ = "rcl_interfaces/DescribeParametersResponse"
    descriptors: list[ParameterDescriptor] = msgspec.field(default_factory=list)


class GetParameterTypesRequest(Message):
    __msgtype__ = "rcl_interfaces/GetParameterTypesRequest"
    names: list[str] = msgspec.field(default_factory=list)


class GetParameterTypesResponse(Message):
    __msgtype__ = "rcl_interfaces/GetParameterTypesResponse"
    types: list[Byte] = msgspec.field(default_factory=list)


class GetParametersRequest(Message):
    __msgtype__ = "rcl_interfaces/GetParametersRequest"
    names: list[str] = msgspec.field(default_factory=list)


class GetParametersResponse(Message):
    __msgtype__ = "rcl_interfaces/GetParametersResponse"
    values: list[ParameterValue] = msgspec.field(default_factory=list)


class SetParametersRequest(Message):
    __msgtype__ = "rcl_interfaces/SetParametersRequest"
    parameters: list[Parameter] = msgspec.field(default_factory=list)


class SetParametersResponse(Message):
    __msgtype__ = "rcl_interfaces/SetParametersResponse"
    results: list[SetParametersResult] = msgspec.field(default_factory=list)


class SetParametersAtomicallyRequest(Message):
    __msgtype__ = "rcl_interfaces/SetParametersAtomicallyRequest"
    parameters: list[Parameter] = msgspec.field(default_factory=list)


class SetParametersAtomicallyResponse(Message):
    __msgtype__ = "rcl_interfaces/SetParametersAtomicallyResponse"
    result: SetParametersResult = msgspec.field(default_factory=SetParametersResult)


ListParameters = define_service("rcl_interfaces/ListParameters", ListParametersRequest,
                                ListParametersResponse)
DescribeParameters = define_service("rcl_interfaces/DescribeParameters",
                                    DescribeParametersRequest, DescribeParametersResponse)
GetParameterTypes = define_service("rcl_interfaces/GetParameterTypes", GetParameterTypesRequest,
                                   GetParameterTypesResponse)
GetParameters = define_service("rcl_interfaces/GetParameters", GetParametersRequest,
                               GetParametersResponse)
SetParameters = define_service("rcl_interfaces/SetParameters", SetParametersRequest,
                               SetParametersResponse)
SetParametersAtomically = define_service("rcl_interfaces/SetParametersAtomically",
                                         SetParametersAtomicallyRequest,
                                         SetParametersAtomicallyResponse)


# Generated by `zenros interface generate` from the ROS 2 definitions (Kilted).

class LoggerLevel(Message):
    """All available logger levels; these correspond to the enum in rcutils/logger.h"""

    __msgtype__ = "rcl_interfaces/LoggerLevel"
    LOG_LEVEL_UNKNOWN: ClassVar[int] = 0
    LOG_LEVEL_DEBUG: ClassVar[int] = 10
    LOG_LEVEL_INFO: ClassVar[int] = 20
    LOG_LEVEL_WARN: ClassVar[int] = 30
    LOG_LEVEL_ERROR: ClassVar[int] = 40
    LOG_LEVEL_FATAL: ClassVar[int] = 50
    name: str = ""
    level: UInt32 = 0


class ParameterEventDescriptors(Message):
    """This message contains descriptors of a parameter event.
    It was an atomic update.
    A specific parameter name can only be in one of the three sets.
    """

    __msgtype__ = "rcl_interfaces/ParameterEventDescriptors"
    new_parameters: list[ParameterDescriptor] = msgspec.field(default_factory=list)
    changed_parameters: list[ParameterDescriptor] = msgspec.field(default_factory=list)
    deleted_parameters: list[ParameterDescriptor] = msgspec.field(default_factory=list)


class SetLoggerLevelsResult(Message):
    """True when succeed, false when failed."""

    __msgtype__ = "rcl_interfaces/SetLoggerLevelsResult"
    successful: bool = False
    reason: str = ""


class GetLoggerLevelsRequest(Message):
    """A list of logger names to get."""

    __msgtype__ = "rcl_interfaces/GetLoggerLevelsRequest"
    names: list[str] = msgspec.field(default_factory=list)


class GetLoggerLevelsResponse(Message):
    """List of logger levels which is the same order as the provided names. If a
    logger was not yet set, the value will have 'unknown' as the value.
    """

    __msgtype__ = "rcl_interfaces/GetLoggerLevelsResponse"
    levels: list[LoggerLevel] = msgspec.field(default_factory=list)


class SetLoggerLevelsRequest(Message):
    """A list of loggers to set."""

    __msgtype__ = "rcl_interfaces/SetLoggerLevelsRequest"
    levels: list[LoggerLevel] = msgspec.field(default_factory=list)


class SetLoggerLevelsResponse(Message):
    """Indicates whether setting each logger succeeded or not and why."""

    __msgtype__ = "rcl_interfaces/SetLoggerLevelsResponse"
    results: list[SetLoggerLevelsResult] = msgspec.field(default_factory=list)


GetLoggerLevels = define_service(
    "rcl_interfaces/GetLoggerLevels", GetLoggerLevelsRequest, GetLoggerLevelsResponse)
SetLoggerLevels = define_service(
    "rcl_interfaces/SetLoggerLevels", SetLoggerLevelsRequest, SetLoggerLevelsResponse)
