"""How a `Subscription` receives samples from Zenoh: one receiver class per kind of topic.

* `LatchedReceiver`: an advanced subscriber that also fetches the publishers' cached last
  samples (QOS_LATCHED), a callback per sample on Zenoh's thread.
* `BulkReceiver`: a callback per sample on Zenoh's thread, for large samples (maps, scans):
  each one leaves Zenoh's shared-memory pool as soon as it is handled, where a queue would
  hold the pool (measured: 1 MiB 0.94-1.05x raw this way, 0.79-1.0x through a channel).
* `ReliableReceiver`: Zenoh queues samples in a channel without taking the GIL (its default
  FIFO, pushing back when full: nothing dropped), and one thread of zenoh-python's drains it
  (an indirect callback; measured faster than a per-sample callback on Zenoh's thread). That
  thread waits without waking: one that reads a channel itself wakes ten times a second to
  check for signals (docs/fleet.md).
* `BestEffortReceiver`: the last ``depth`` samples in a ring, drained by a thread of ours.

`receiver_for` picks one. Each ``close()`` undeclares and waits (2 s at most) for a sample
being handled, unless called from the very thread that handles it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, Protocol

import zenoh
from zenoh import ext as zext

from .qos import QoSProfile, Reliability

__all__ = ["BestEffortReceiver", "BulkReceiver", "LatchedReceiver", "Receiver",
           "ReliableReceiver", "SamplePath", "receiver_for"]

OnSample = Callable[[zenoh.Sample], None]
SamplePath = Callable[[Callable[[threading.Thread], None]], OnSample]
"""``path(first)``: the per-sample function of a queue-drained receiver; it calls
``first(thread)`` with the thread that drains the queue, on its first sample."""

CLOSE_WAIT = 2.0  # seconds close() waits for a sample being handled


class Receiver(Protocol):
    def close(self) -> None:
        """Stop receiving; a sample being handled (on another thread) finishes first."""


class LatchedReceiver:
    """Latched history, including that of publishers in this very session, comes from the
    advanced subscriber's history query (live in-process samples from the context's bus)."""

    def __init__(self, session: zenoh.Session, key: str, depth: int,
                 on_sample: OnSample) -> None:
        self._sub: Any = zext.declare_advanced_subscriber(
            session, key, on_sample, allowed_origin=zenoh.Locality.REMOTE,
            history=zext.HistoryConfig(detect_late_publishers=True, max_samples=depth),
            recovery=zext.RecoveryConfig(heartbeat=True, periodic_queries=None),
            subscriber_detection=True,
        )

    def close(self) -> None:
        self._sub.undeclare()


class BulkReceiver:
    """Large samples: a callback per sample on Zenoh's thread."""

    def __init__(self, session: zenoh.Session, key: str, on_sample: OnSample) -> None:
        self._sub = session.declare_subscriber(key, on_sample,
                                               allowed_origin=zenoh.Locality.REMOTE)

    def close(self) -> None:
        self._sub.undeclare()  # type: ignore[no-untyped-call]


class ReliableReceiver:
    """Zenoh's FIFO channel, drained by zenoh-python's callback thread."""

    def __init__(self, session: zenoh.Session, key: str, path: SamplePath, name: str) -> None:
        self._name = name
        self._thread: threading.Thread | None = None  # the thread that drains the channel
        self._drained = threading.Event()  # that thread has ended
        self._sub = session.declare_subscriber(
            key, zenoh.handlers.Callback(path(self._drains_here), self._drained.set),
            allowed_origin=zenoh.Locality.REMOTE,
        )

    def _drains_here(self, thread: threading.Thread) -> None:
        self._thread = thread
        thread.name = self._name

    def close(self) -> None:
        self._sub.undeclare()  # type: ignore[no-untyped-call]
        if self._thread is not threading.current_thread():
            self._drained.wait(CLOSE_WAIT)


class BestEffortReceiver:
    """A ring of the last ``depth`` samples, drained by a thread of ours."""

    def __init__(self, session: zenoh.Session, key: str, depth: int, path: SamplePath,
                 name: str) -> None:
        self._sub: Any = session.declare_subscriber(
            key, zenoh.handlers.RingChannel(depth), allowed_origin=zenoh.Locality.REMOTE)
        # Taken here, not in the thread: reading `.handler` while `close()` undeclares the
        # subscriber on another thread raises pyo3's "Already mutably borrowed".
        self._channel = self._sub.handler
        self._take = path(lambda _thread: None)  # drained on the thread below, named so
        self._pump = threading.Thread(target=self._drain, name=name, daemon=True)
        self._pump.start()

    def _drain(self) -> None:
        take = self._take
        try:
            for sample in self._channel:  # ends when the subscriber is undeclared
                take(sample)
        except zenoh.ZError:  # the channel closed under us at shutdown
            return

    def close(self) -> None:
        self._sub.undeclare()
        if self._pump is not threading.current_thread():
            self._pump.join(CLOSE_WAIT)


def receiver_for(session: zenoh.Session, key: str, qos: QoSProfile, bulk: bool,
                 on_sample: OnSample, path: SamplePath, name: str) -> Receiver:
    """The receiver for a topic of ``qos`` (``bulk``: its type has large samples):
    ``on_sample`` serves the per-sample kinds, ``path`` the queue-drained ones."""
    if qos.latched:
        return LatchedReceiver(session, key, qos.depth, on_sample)
    if bulk:
        return BulkReceiver(session, key, on_sample)
    if qos.reliability == Reliability.RELIABLE:
        return ReliableReceiver(session, key, path, name)
    return BestEffortReceiver(session, key, qos.depth, path, name)
