"""What a lifecycle manager (`zenros.lifecycle.manager`) reports on ``~/status``."""

from __future__ import annotations

import msgspec

from ...message import Message
from ..builtin_interfaces import Time

__all__ = ["LifecycleManagerStatus"]


class LifecycleManagerStatus(Message):
    """The manager's view after each step: ``state`` is ``idle``, ``starting``, ``active``,
    ``paused``, ``reset``, ``shutdown``, ``failed`` (a command did not complete), ``down``
    (``lost`` stopped its heartbeat, the others were taken down), ``respawning`` (waiting for
    every node to answer again) or ``gave_up`` (they did not within
    bond_respawn_max_duration)."""

    __msgtype__ = "zenros_msgs/LifecycleManagerStatus"
    stamp: Time = msgspec.field(default_factory=Time)
    state: str = "idle"
    active: bool = False
    nodes: list[str] = msgspec.field(default_factory=list)
    lost: str = ""
    message: str = ""
