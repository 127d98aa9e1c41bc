"""`TransformListener`: fills a `Buffer` from ``/tf`` and latched ``/tf_static``."""

from __future__ import annotations

import logging
import threading
from typing import TYPE_CHECKING

from ..clock import Clock
from ..msgs.tf2_msgs import TFMessage
from ..qos import Durability, QoSProfile
from .buffer import Buffer
from .stamps import NS, format_ns

if TYPE_CHECKING:
    from ..node import Node
    from ..pubsub import Subscription

__all__ = [
    "DEFAULT_AUTHORITY",
    "DYNAMIC_LISTENER_QOS",
    "STATIC_LISTENER_QOS",
    "ClockJumpGuard",
    "TransformListener",
]

DEFAULT_AUTHORITY = "default_authority"
"""The authority tf2_ros's listener records: a TFMessage does not say who sent it."""

DYNAMIC_LISTENER_QOS = QoSProfile(depth=100)
"""``/tf``: reliable, volatile, depth 100 (tf2_ros's ``DynamicListenerQoS``)."""

STATIC_LISTENER_QOS = QoSProfile(depth=100, durability=Durability.TRANSIENT_LOCAL)
"""``/tf_static``: latched, depth 100, so the latest message of every static broadcaster
arrives (tf2_ros's ``StaticListenerQoS``)."""


class ClockJumpGuard:
    """Clears a buffer when a simulated clock runs backwards (a reset, a bag loop), as
    tf2_ros does; otherwise the new, older stamps would be refused as old data.

    Only clocks of kind ``"ros"`` (sim time, `ManualClock`) are watched: like ROS 2, a wall
    clock stepped back by NTP leaves the buffer alone. Call `check` before each insert.
    """

    def __init__(self, buffer: Buffer, clock: Clock, logger: logging.Logger) -> None:
        self._buffer = buffer
        self._clock = clock
        self._logger = logger
        self.active = clock.kind == "ros"
        self._last = 0
        self._lock = threading.Lock()
        self.jumps = 0

    def check(self) -> None:
        """Compare the clock with the last time seen; clear the buffer if it went back."""
        if not self.active:
            return
        t = self._clock.now()
        now = t.sec * NS + t.nanosec
        with self._lock:
            last, self._last = self._last, now
            if now >= last:
                return
            self.jumps += 1
        self._logger.warning(
            "clock jumped back from %s to %s: clearing the TF buffer", format_ns(last),
            format_ns(now),
        )
        self._buffer.clear()


class TransformListener:
    """Subscribes to ``/tf`` and ``/tf_static`` and stores every link in ``buffer``
    (tf2_ros.TransformListener).

    Callbacks run on Zenoh's threads (the buffer is thread safe), so nothing needs
    spinning; a thread may block in ``buffer.lookup_transform(..., timeout=...)`` while
    data arrives. With ``use_sim_time``, the buffer is cleared when the node's clock jumps
    back. Links are recorded with the authority ``"default_authority"``, as in ROS 2.

    Args:
        buffer: the buffer to fill.
        node: the node whose subscriptions (and clock) are used.
        spin_thread: accepted for tf2_ros compatibility; no thread is ever needed.
        qos: ``/tf``'s QoS (default `DYNAMIC_LISTENER_QOS`).
        static_qos: ``/tf_static``'s QoS (default `STATIC_LISTENER_QOS`).
    """

    def __init__(
        self, buffer: Buffer, node: Node, *, spin_thread: bool = False,
        qos: QoSProfile | int | None = None, static_qos: QoSProfile | int | None = None,
    ) -> None:
        self.buffer = buffer
        self._node = node
        self.guard = ClockJumpGuard(buffer, node.get_clock(), node.logger)
        self._subs: list[Subscription[TFMessage]] = [
            node.create_subscription(TFMessage, "/tf", self.callback,
                                     qos if qos is not None else DYNAMIC_LISTENER_QOS),
            node.create_subscription(
                TFMessage, "/tf_static", self.static_callback,
                static_qos if static_qos is not None else STATIC_LISTENER_QOS,
            ),
        ]

    def callback(self, msg: TFMessage) -> None:
        """Store the dynamic links of one ``/tf`` message."""
        self.guard.check()
        set_transform = self.buffer.set_transform
        for t in msg.transforms:
            set_transform(t, DEFAULT_AUTHORITY)

    def static_callback(self, msg: TFMessage) -> None:
        """Store the static links of one ``/tf_static`` message."""
        for t in msg.transforms:
            self.buffer.set_transform_static(t, DEFAULT_AUTHORITY)

    def unregister(self) -> None:
        """Stop listening (tf2_ros's name); the buffer keeps what it has."""
        subs, self._subs = self._subs, []
        for s in subs:
            self._node.destroy(s)

    close = unregister
