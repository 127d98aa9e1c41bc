"""rcl_interfaces: Log, the payload of /rosout."""

from __future__ import annotations

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
