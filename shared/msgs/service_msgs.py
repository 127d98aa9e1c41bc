"""service_msgs: ServiceEventInfo, what each service event says (ROS 2's service
introspection, `zenros.service_events`)."""

from __future__ import annotations

from typing import Annotated

import msgspec

from ..message import Message
from .builtin_interfaces import Time

__all__ = ["ServiceEventInfo"]

_Byte = Annotated[int, msgspec.Meta(ge=0, le=255)]
_Gid = Annotated[list[_Byte], msgspec.Meta(min_length=16, max_length=16)]


class ServiceEventInfo(Message):
    """Which side saw what (``event_type``), when, from which client and its request's
    sequence number."""

    __msgtype__ = "service_msgs/ServiceEventInfo"
    event_type: _Byte = 0
    stamp: Time = msgspec.field(default_factory=Time)
    client_gid: _Gid = msgspec.field(default_factory=lambda: [0] * 16)
    sequence_number: int = 0

    REQUEST_SENT = 0
    REQUEST_RECEIVED = 1
    RESPONSE_SENT = 2
    RESPONSE_RECEIVED = 3
