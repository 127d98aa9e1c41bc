"""std_srvs: Empty, Trigger and SetBool services."""

from __future__ import annotations

from ..message import Message, define_service


class EmptyRequest(Message):
    __msgtype__ = "std_srvs/EmptyRequest"


class EmptyResponse(Message):
    __msgtype__ = "std_srvs/EmptyResponse"


class TriggerRequest(Message):
    __msgtype__ = "std_srvs/TriggerRequest"


class TriggerResponse(Message):
    __msgtype__ = "std_srvs/TriggerResponse"
    success: bool = False
    message: str = ""


class SetBoolRequest(Message):
    __msgtype__ = "std_srvs/SetBoolRequest"
    data: bool = False


class SetBoolResponse(Message):
    __msgtype__ = "std_srvs/SetBoolResponse"
    success: bool = False
    message: str = ""


Empty = define_service("std_srvs/Empty", EmptyRequest, EmptyResponse)
Trigger = define_service("std_srvs/Trigger", TriggerRequest, TriggerResponse)
SetBool = define_service("std_srvs/SetBool", SetBoolRequest, SetBoolResponse)
