"""`TimeSynchronizer`: ROS's ExactTime policy, one message per input with the same stamp."""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any

from .filter import SimpleFilter, stamp_ns

__all__ = ["TimeSynchronizer", "connect_inputs"]


def connect_inputs(sync: Any, fs: Sequence[SimpleFilter]) -> None:
    """Feed input ``i`` of ``sync`` (its ``add(msg, i)``) from filter ``fs[i]``."""
    if sync.n_inputs and len(fs) != sync.n_inputs:
        raise ValueError(f"{type(sync).__name__} has {sync.n_inputs} inputs, got {len(fs)}")
    for i, f in enumerate(fs):
        f.registerCallback(sync.add, i)


class TimeSynchronizer(SimpleFilter):
    """Emits ``(m_0, ..., m_n-1)`` once every input has a message with the same header stamp.

    As ROS's ExactTime: a complete set is signalled, and every incomplete set as old or
    older is then dropped (to ``registerDropCallback``'s callbacks, ``None`` for the inputs
    without a message); beyond ``queue_size`` incomplete stamps the oldest goes the same way.
    Headerless messages are dropped (an exact match needs stamps)."""

    def __init__(self, fs: Sequence[SimpleFilter], queue_size: int) -> None:
        super().__init__()
        if queue_size < 1:
            raise ValueError(f"queue_size must be at least 1, got {queue_size}")
        if len(fs) < 2:
            raise ValueError(f"a synchronizer needs at least 2 inputs, got {len(fs)}")
        self.queue_size = queue_size
        self.n_inputs = len(fs)
        self._tuples: dict[int, list[Any]] = {}
        self._last_signal: int | None = None
        self._lock = threading.Lock()
        self._drop = SimpleFilter()
        connect_inputs(self, fs)

    def connectInput(self, fs: Sequence[SimpleFilter]) -> None:
        connect_inputs(self, fs)

    def registerDropCallback(self, cb: Callable[..., Any], *args: Any) -> int:
        return self._drop.registerCallback(cb, *args)

    def add(self, msg: Any, index: int) -> None:
        """Input ``index`` received ``msg``."""
        t = stamp_ns(msg)
        if t is None or not 0 <= index < self.n_inputs:
            return
        out: list[tuple[list[Any], bool]] = []  # (set, complete) in order, signalled unlocked
        with self._lock:
            slot = self._tuples.setdefault(t, [None] * self.n_inputs)
            slot[index] = msg
            if all(m is not None for m in slot):
                out.append((slot, True))
                self._last_signal = t
                del self._tuples[t]
                for old in sorted(k for k in self._tuples if k <= t):
                    out.append((self._tuples.pop(old), False))
            while len(self._tuples) > self.queue_size:
                oldest = min(self._tuples)
                out.append((self._tuples.pop(oldest), False))
        for msgs, complete in out:
            (self.signalMessage if complete else self._drop.signalMessage)(*msgs)
