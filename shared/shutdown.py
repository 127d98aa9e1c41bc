"""Telling a node to shut down: the `Shutdown` message and the node-side listener.

The master sends it when a newer node takes an older one's name (ROS 1 behaviour). The
message names one node *instance* (name, session id and start time), so the newer node of
the same name ignores it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

import zenoh

from .codec import codec_for
from .errors import CodecError
from .message import Message

if TYPE_CHECKING:
    from .node import Node

__all__ = ["SHUTDOWN_TOPIC", "Shutdown", "ShutdownListener", "install_shutdown_listener",
           "send_shutdown"]

SHUTDOWN_TOPIC = "/zenros/shutdown"
"""Where shutdown requests travel (a topic, so ``z_sub`` shows them as JSON)."""


class Shutdown(Message, kw_only=True):
    """A request that one node instance shut down."""

    __msgtype__ = "zenros_msgs/Shutdown"
    node: str = ""
    """The fully qualified name of the node to stop."""
    zid: str = ""
    """Its Zenoh session id."""
    start_ns: int = 0
    """Its start time (ns since the epoch), as in its liveliness token."""
    reason: str = ""
    by: str = ""
    """The node that asks (the master)."""


_CODEC = codec_for(Shutdown)


def send_shutdown(session: zenoh.Session, key: str, request: Shutdown) -> None:
    """Publish ``request`` on ``key`` (the key of `SHUTDOWN_TOPIC`), reliably."""
    session.put(key, _CODEC.encode(request), encoding=_CODEC.encoding,
                congestion_control=zenoh.CongestionControl.BLOCK)


class ShutdownListener:
    """Calls ``on_shutdown()`` once when a `Shutdown` for this node instance arrives."""

    def __init__(self, node: Node, on_shutdown: Callable[[], None]) -> None:
        ctx = node.context
        self._node = node
        self._on_shutdown = on_shutdown
        self._fired = threading.Event()
        self._sub = ctx.session.declare_subscriber(ctx.keys.topic(SHUTDOWN_TOPIC), self._on_sample)
        self.closed = False

    @property
    def fired(self) -> bool:
        return self._fired.is_set()

    def _on_sample(self, sample: zenoh.Sample) -> None:
        try:
            msg = _CODEC.decode(sample.payload.to_bytes())
        except CodecError as exc:
            self._node.logger.warning("ignoring a malformed shutdown request: %s", exc)
            return
        node = self._node
        if (msg.node, msg.zid, msg.start_ns) != (node.fqn, node.context.zid, node.start_ns):
            return
        if self._fired.is_set():
            return
        self._fired.set()
        node.logger.error("shutting down: %s (asked by %s)", msg.reason or "no reason given",
                          msg.by or "an unnamed node")
        # Off Zenoh's thread: on_shutdown may close the node, and with it this subscriber.
        threading.Thread(target=self._on_shutdown, name="zenros-shutdown", daemon=True).start()

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self._sub.undeclare()  # type: ignore[no-untyped-call]


def install_shutdown_listener(node: Node, on_shutdown: Callable[[], None]) -> ShutdownListener:
    """Make ``node`` obey shutdown requests: log the reason, then call ``on_shutdown()``.

    The runtime passes its stop event's ``set``, so the process closes the node and exits.
    The listener is closed with the node.

    Args:
        node: the node to protect; the request must name its FQN, session and start time.
        on_shutdown: called once, on a thread of its own.

    Returns:
        The listener (``close()`` undeclares it; closing the node does that too).
    """
    listener = ShutdownListener(node, on_shutdown)
    node.add_waitable(listener)
    return listener
