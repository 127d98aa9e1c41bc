"""galileo_msgs: the robot API's status and native commands (docs/robot-api.md §4, §12).

The JSON of these types is the API's own (§4): camelCase fields and a ROS 1 style header
(``seq``, ``stamp.secs``/``stamp.nsecs``, ``frame_id``), so ``galileo/status`` on the wire,
``GET /system/galileo_status`` and the WebSocket stream are the same document.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

from ..message import Message

__all__ = ["GalileoHeader", "GalileoNativeCmds", "GalileoStamp", "GalileoStatus"]

UInt8 = Annotated[int, msgspec.Meta(ge=0, le=255)]
UInt32 = Annotated[int, msgspec.Meta(ge=0, le=0xFFFFFFFF)]


class GalileoStamp(Message):
    """A ROS 1 time: ``secs`` and ``nsecs``."""

    __msgtype__ = "galileo_msgs/Stamp"
    secs: int = 0
    nsecs: int = 0


class GalileoHeader(Message):
    """The ROS 1 header the API's JSON carries (``seq``, ``stamp``, ``frame_id``)."""

    __msgtype__ = "galileo_msgs/Header"
    seq: UInt32 = 0
    stamp: GalileoStamp = msgspec.field(default_factory=GalileoStamp)
    frame_id: str = "map"


class GalileoStatus(Message, kw_only=True):
    """The robot's whole state in one message (§4); codes as the spec's table."""

    __msgtype__ = "galileo_msgs/GalileoStatus"
    header: GalileoHeader = msgspec.field(default_factory=GalileoHeader)
    navStatus: int = 0
    visualStatus: int = -1
    mapStatus: int = 0
    gcStatus: int = 0
    gbaStatus: int = 0
    chargeStatus: int = 0
    loopStatus: int = 0
    power: float = 0.0
    targetNumID: int = -1
    targetStatus: int = 0
    targetDistance: float = -1.0
    angleGoalStatus: int = -1
    controlSpeedX: float = 0.0
    controlSpeedTheta: float = 0.0
    currentSpeedX: float = 0.0
    currentSpeedTheta: float = 0.0
    currentPosX: float = -1.0
    currentPosY: float = -1.0
    currentAngle: float = -1.0
    busyStatus: int = 0


class GalileoNativeCmds(Message):
    """A native command (§12.1): ``length`` bytes of ``data`` (codes in §12.3)."""

    __msgtype__ = "galileo_msgs/GalileoNativeCmds"
    header: GalileoHeader = msgspec.field(default_factory=GalileoHeader)
    length: UInt32 = 0
    data: list[UInt8] = msgspec.field(default_factory=list)
