"""`DeliveryGate`: holds the callbacks of endpoints a node creates in ``setup()`` until
``setup()`` has returned, so no callback ever sees a half-built node."""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from typing import Any

__all__ = ["DeliveryGate", "Held"]


class DeliveryGate:
    """Closed while a node's ``setup()`` runs; `open` once it has returned.

    Endpoints created meanwhile hold what arrives: subscriptions keep the last ``depth``
    messages (their QoS) in a `Held` and get them, in order, when the gate opens; services
    and action servers leave requests queued in Zenoh (their serving thread `wait`s);
    timers skip the ticks that fall before. `abandon` (the node closed before its setup
    returned) releases waiters and drops what is held.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._event = threading.Event()
        self._flushes: list[Callable[[], None]] = []
        self.is_open = False     # read without the lock: it only ever goes False -> True
        self.abandoned = False

    def wait(self, timeout: float | None = None) -> bool:
        """Block until the gate is open (or abandoned); False on timeout."""
        return self._event.wait(timeout)

    def _defer(self, flush: Callable[[], None]) -> bool:
        """Locked by the caller: have ``flush`` called before the gate opens."""
        self._flushes.append(flush)
        return True

    def open(self) -> None:
        """Deliver everything held (on this thread, in arrival order per endpoint), then let
        callbacks through. Messages arriving during the flush are held and flushed too."""
        while True:
            with self._lock:
                flushes, self._flushes = self._flushes, []
                if not flushes:
                    self.is_open = True
                    self._event.set()
                    return
            for flush in flushes:
                flush()

    def abandon(self) -> None:
        """Open without delivering: the node is closing; held messages are dropped."""
        with self._lock:
            self.abandoned = True
            self._flushes = []
            self.is_open = True
            self._event.set()


class Held:
    """``fn(arg)`` through a gate: called at once when the gate is open, else kept (the last
    ``depth`` args) and called when it opens."""

    __slots__ = ("_fn", "_gate", "_pending", "_queued")

    def __init__(self, gate: DeliveryGate, fn: Callable[[Any], Any], depth: int) -> None:
        self._gate = gate
        self._fn = fn
        self._pending: deque[Any] = deque(maxlen=max(1, depth))
        self._queued = False

    def __call__(self, arg: Any) -> None:
        gate = self._gate
        if not gate.is_open:
            with gate._lock:
                if not gate.is_open:
                    self._pending.append(arg)
                    if not self._queued:
                        self._queued = gate._defer(self._flush)
                    return
        if gate.abandoned:
            return
        self._fn(arg)

    def _flush(self) -> None:
        with self._gate._lock:
            items = list(self._pending)
            self._pending.clear()
            self._queued = False
        for arg in items:
            self._fn(arg)
