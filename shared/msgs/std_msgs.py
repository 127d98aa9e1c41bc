"""std_msgs: Header and the primitive wrappers."""

from __future__ import annotations

import msgspec

from ..message import Message
from .builtin_interfaces import Time


class Header(Message):
    """Stamp and coordinate frame of a stamped message (ROS 2 layout; a ROS 1 `seq` is ignored)."""

    __msgtype__ = "std_msgs/Header"
    stamp: Time = msgspec.field(default_factory=Time)
    frame_id: str = ""


class Empty(Message):
    __msgtype__ = "std_msgs/Empty"


class String(Message):
    __msgtype__ = "std_msgs/String"
    data: str = ""


class Bool(Message):
    __msgtype__ = "std_msgs/Bool"
    data: bool = False


class Int32(Message):
    __msgtype__ = "std_msgs/Int32"
    data: int = 0


class Int64(Message):
    __msgtype__ = "std_msgs/Int64"
    data: int = 0


class UInt8(Message):
    __msgtype__ = "std_msgs/UInt8"
    data: int = 0


class Float32(Message):
    __msgtype__ = "std_msgs/Float32"
    data: float = 0.0


class Float64(Message):
    __msgtype__ = "std_msgs/Float64"
    data: float = 0.0


class ColorRGBA(Message):
    __msgtype__ = "std_msgs/ColorRGBA"
    r: float = 0.0
    g: float = 0.0
    b: float = 0.0
    a: float = 0.0
