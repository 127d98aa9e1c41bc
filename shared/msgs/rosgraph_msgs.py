"""rosgraph_msgs: Clock, the payload of /clock for simulated time."""

from __future__ import annotations

import msgspec

from ..message import Message
from .builtin_interfaces import Time


class Clock(Message):
    __msgtype__ = "rosgraph_msgs/Clock"
    clock: Time = msgspec.field(default_factory=Time)
