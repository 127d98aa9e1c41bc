"""The filter chain's links: `SimpleFilter` (callbacks) and `Subscriber` (a topic as a filter)."""

from __future__ import annotations

import itertools
import threading
from collections.abc import Callable
from typing import Any

from ..clock import Clock, SystemClock
from ..qos import QoSProfile

__all__ = ["SimpleFilter", "Subscriber", "stamp_ns"]


class SimpleFilter:
    """A filter's output: ``registerCallback(cb, *args)`` and ``signalMessage(*msgs)``.

    Each registered callback gets the messages of a signal, then its own ``args``."""

    def __init__(self) -> None:
        self._callbacks: dict[int, tuple[Callable[..., Any], tuple[Any, ...]]] = {}
        self._ids = itertools.count()
        self._cb_lock = threading.Lock()

    def registerCallback(self, cb: Callable[..., Any], *args: Any) -> int:
        """Call ``cb(*msgs, *args)`` on every signal; returns a connection id."""
        with self._cb_lock:
            conn = next(self._ids)
            self._callbacks[conn] = (cb, args)
        return conn

    def disconnect(self, conn: int) -> None:
        """Stop calling the callback ``registerCallback`` returned ``conn`` for."""
        with self._cb_lock:
            self._callbacks.pop(conn, None)

    def signalMessage(self, *msgs: Any) -> None:
        with self._cb_lock:
            callbacks = list(self._callbacks.values())
        for cb, args in callbacks:
            cb(*(msgs + args))


class Subscriber(SimpleFilter):
    """A zenros subscription as the head of a filter chain (rclpy's ``Subscriber(node, Type,
    topic, qos_profile)``): each message received is signalled on."""

    def __init__(self, node: Any, msg_type: type, topic: str,
                 qos_profile: QoSProfile | int = 10, **kwargs: Any) -> None:
        super().__init__()
        self.node = node
        self.topic = topic
        self.sub = node.create_subscription(msg_type, topic, self.callback, qos_profile,
                                            **kwargs)

    def callback(self, msg: Any) -> None:
        self.signalMessage(msg)

    def getTopic(self) -> str:
        return str(self.sub.topic)

    def close(self) -> None:
        """Close the subscription (the node would at its own close)."""
        self.node.destroy(self.sub)

    def __getattr__(self, key: str) -> Any:
        if key == "sub":  # not yet set: __init__ failed before it
            raise AttributeError(key)
        return getattr(self.sub, key)


def stamp_ns(msg: Any) -> int | None:
    """``msg.header.stamp`` in nanoseconds, None for a message without one.

    Takes zenros's `Time`, rclpy's `Time` (``nanoseconds``) and any ``sec``/``nanosec`` pair."""
    header = getattr(msg, "header", None)
    stamp = getattr(header, "stamp", None)
    if stamp is None:
        return None
    ns = getattr(stamp, "nanoseconds", None)
    if isinstance(ns, int):
        return ns
    sec, nanosec = getattr(stamp, "sec", None), getattr(stamp, "nanosec", None)
    if isinstance(sec, int) and isinstance(nanosec, int):
        return sec * 1_000_000_000 + nanosec
    return None


def clock_of(source: Any, clock: Clock | None) -> Clock:
    """The clock that stamps headerless messages: ``clock``, else that of the node behind a
    `Subscriber` input, else the system clock (rclpy's ROSClock without sim time)."""
    if clock is not None:
        return clock
    node = getattr(source, "node", None)
    if node is not None and hasattr(node, "get_clock"):
        c: Clock = node.get_clock()
        return c
    return SystemClock()
