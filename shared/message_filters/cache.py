"""`Cache`: the last ``cache_size`` messages of a filter, queried by header stamp."""

from __future__ import annotations

import logging
import threading
from collections import deque
from typing import Any

from ..clock import Clock
from ..msgs.builtin_interfaces import Time
from .filter import SimpleFilter, clock_of, stamp_ns

__all__ = ["Cache"]

log = logging.getLogger("zenros.message_filters")

StampLike = Time | int  # a `Time`, or nanoseconds


def _ns(t: Any) -> int:
    if isinstance(t, int):
        return t
    ns = getattr(t, "nanoseconds", None)
    if isinstance(ns, int):
        return ns
    raise TypeError(f"expected a Time or integer nanoseconds, got {type(t).__name__}")


class Cache(SimpleFilter):
    """rclpy's ``Cache(f, cache_size=1, allow_headerless=False)``: keeps the newest
    ``cache_size`` messages by arrival and passes each on.

    Queries compare header stamps, inclusive at both ends: ``getInterval(from, to)`` (in
    arrival order), ``getElemAfterTime(t)`` (the oldest at or after ``t``),
    ``getElemBeforeTime(t)`` (the newest at or before ``t``), ``getLatestTime()``,
    ``getOldestTime()``, ``getLast()``. A headerless message is stamped with the input's
    node clock (or ``clock``) if ``allow_headerless``, else dropped with a warning."""

    def __init__(self, f: SimpleFilter | None = None, cache_size: int = 1,
                 allow_headerless: bool = False, *, clock: Clock | None = None) -> None:
        super().__init__()
        if cache_size < 1:
            raise ValueError(f"cache_size must be at least 1, got {cache_size}")
        self.cache_size = cache_size
        self.allow_headerless = allow_headerless
        self._items: deque[tuple[int, Any]] = deque(maxlen=cache_size)
        self._lock = threading.Lock()
        self._clock = clock
        self._warned = False
        if f is not None:
            self.connectInput(f)

    def connectInput(self, f: SimpleFilter) -> None:
        self._clock = clock_of(f, self._clock)
        f.registerCallback(self.add)

    def add(self, msg: Any) -> None:
        ns = stamp_ns(msg)
        if ns is None:
            if not self.allow_headerless:
                if not self._warned:
                    self._warned = True
                    log.warning("Cache: dropping %s, which has no header.stamp "
                                "(allow_headerless=True stamps it with the clock's now)",
                                type(msg).__name__)
                return
            ns = clock_of(None, self._clock).now().nanoseconds
        with self._lock:
            self._items.append((ns, msg))
        self.signalMessage(msg)

    def getInterval(self, from_stamp: StampLike, to_stamp: StampLike) -> list[Any]:
        lo, hi = _ns(from_stamp), _ns(to_stamp)
        if lo > hi:
            raise ValueError(f"getInterval: from_stamp ({lo} ns) is after to_stamp ({hi} ns)")
        with self._lock:
            return [m for t, m in self._items if lo <= t <= hi]

    def getElemAfterTime(self, stamp: StampLike) -> Any | None:
        t0 = _ns(stamp)
        with self._lock:
            return next((m for t, m in self._items if t >= t0), None)

    def getElemBeforeTime(self, stamp: StampLike) -> Any | None:
        t0 = _ns(stamp)
        with self._lock:
            return next((m for t, m in reversed(self._items) if t <= t0), None)

    def getLatestTime(self) -> Time | None:
        with self._lock:
            return Time.from_nanoseconds(self._items[-1][0]) if self._items else None

    getLastestTime = getLatestTime  # rclpy's spelling

    def getOldestTime(self) -> Time | None:
        with self._lock:
            return Time.from_nanoseconds(self._items[0][0]) if self._items else None

    def getLast(self) -> Any | None:
        """rclpy's: the oldest message stamped at or after the newest one's stamp."""
        latest = self.getLatestTime()
        return None if latest is None else self.getElemAfterTime(latest)

    def __len__(self) -> int:
        return len(self._items)
