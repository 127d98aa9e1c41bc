"""diagnostic_msgs: DiagnosticArray, DiagnosticStatus, KeyValue; the SelfTest and
AddDiagnostics services (ROS 2's definitions; `zenros.diagnostics` publishes them)."""

from __future__ import annotations

from typing import Annotated, ClassVar

import msgspec

from ..message import Message, define_service
from .std_msgs import Header

Byte = Annotated[int, msgspec.Meta(ge=0, le=255)]


class KeyValue(Message):
    __msgtype__ = "diagnostic_msgs/KeyValue"
    key: str = ""
    value: str = ""


class DiagnosticStatus(Message):
    """One component's state: ``level`` is OK, WARN, ERROR or STALE."""

    __msgtype__ = "diagnostic_msgs/DiagnosticStatus"
    OK: ClassVar[int] = 0
    WARN: ClassVar[int] = 1
    ERROR: ClassVar[int] = 2
    STALE: ClassVar[int] = 3
    level: Byte = 0
    name: str = ""
    message: str = ""
    hardware_id: str = ""
    values: list[KeyValue] = msgspec.field(default_factory=list)


class DiagnosticArray(Message):
    __msgtype__ = "diagnostic_msgs/DiagnosticArray"
    header: Header = msgspec.field(default_factory=Header)
    status: list[DiagnosticStatus] = msgspec.field(default_factory=list)


class SelfTestRequest(Message):
    __msgtype__ = "diagnostic_msgs/SelfTestRequest"


class SelfTestResponse(Message):
    __msgtype__ = "diagnostic_msgs/SelfTestResponse"
    id: str = ""
    passed: Byte = 0
    status: list[DiagnosticStatus] = msgspec.field(default_factory=list)


class AddDiagnosticsRequest(Message):
    __msgtype__ = "diagnostic_msgs/AddDiagnosticsRequest"
    load_namespace: str = ""


class AddDiagnosticsResponse(Message):
    __msgtype__ = "diagnostic_msgs/AddDiagnosticsResponse"
    success: bool = False
    message: str = ""


SelfTest = define_service("diagnostic_msgs/SelfTest", SelfTestRequest, SelfTestResponse)
AddDiagnostics = define_service("diagnostic_msgs/AddDiagnostics", AddDiagnosticsRequest,
                                AddDiagnosticsResponse)
