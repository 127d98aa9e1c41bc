"""bond: the heartbeat two processes exchange to watch each other (ROS 2's bond/Status)."""

from __future__ import annotations

import msgspec

from ..message import Message
from .std_msgs import Header

__all__ = ["Status"]


class Status(Message):
    """One heartbeat of one side (``instance_id``) of the bond ``id``; ``active`` False says
    the side leaves the bond on purpose. The timeouts travel along for debugging."""

    __msgtype__ = "bond/Status"
    header: Header = msgspec.field(default_factory=Header)
    id: str = ""
    instance_id: str = ""
    active: bool = False
    heartbeat_timeout: float = 0.0
    heartbeat_period: float = 0.0
