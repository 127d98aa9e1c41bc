"""`FrameMonitor`: per-frame statistics of received links, the figures tf_monitor shows."""

from __future__ import annotations

import threading
from collections import deque
from dataclasses import dataclass, field

from zenros.msgs.tf_srvs import FrameInfo
from zenros.tf import from_ns

__all__ = ["FrameMonitor"]

NS = 1_000_000_000


@dataclass
class _Frame:
    parent: str
    authority: str
    static: bool
    latest_ns: int = 0
    count: int = 0
    arrivals: deque[float] = field(default_factory=deque)  # monotonic seconds
    delays: deque[float] = field(default_factory=deque)  # seconds, aligned with arrivals


class FrameMonitor:
    """Counts the links of each child frame: who sent the last one, how often they come,
    the newest stamp, and how late they arrive (receiver clock minus stamp).

    Rates and delays cover the links that arrived within the last ``window`` seconds, so a
    frame that stopped shows rate 0 one window later. Thread safe.

    Args:
        window: seconds of arrivals the figures cover.
        max_samples: arrivals kept per frame at most (bounds memory at high rates).
    """

    def __init__(self, window: float = 10.0, max_samples: int = 10_000) -> None:
        if not window > 0:
            raise ValueError(f"window must be > 0 s, got {window}")
        self.window = window
        self.max_samples = max_samples
        self._frames: dict[str, _Frame] = {}
        self._lock = threading.Lock()

    def record(self, child: str, parent: str, authority: str, stamp_ns: int, *,
               static: bool, now_ns: int, arrival: float) -> None:
        """One accepted link.

        Args:
            child, parent: the link's frames (leading '/' already stripped).
            authority: who sent it.
            stamp_ns: its stamp.
            static: whether it came on ``/tf_static``.
            now_ns: the receiver's clock (sim or wall) when it arrived, for the delay.
            arrival: a monotonic time in seconds, for the rate.
        """
        with self._lock:
            f = self._frames.get(child)
            if f is None or f.static != static:
                f = self._frames[child] = _Frame(parent, authority, static)
            f.parent, f.authority = parent, authority
            f.count += 1
            if static:
                f.latest_ns = stamp_ns
                return
            f.latest_ns = max(f.latest_ns, stamp_ns)
            f.arrivals.append(arrival)
            f.delays.append((now_ns - stamp_ns) / NS)
            if len(f.arrivals) > self.max_samples:
                f.arrivals.popleft()
                f.delays.popleft()

    def frames(self, now: float) -> list[FrameInfo]:
        """Every child frame seen, sorted by id, with figures as of monotonic ``now``."""
        out = []
        with self._lock:
            for child in sorted(self._frames):
                f = self._frames[child]
                self._prune(f, now)
                info = FrameInfo(frame_id=child, parent=f.parent, authority=f.authority,
                                 static=f.static, most_recent=from_ns(f.latest_ns),
                                 count=f.count)
                if f.arrivals:
                    span = f.arrivals[-1] - f.arrivals[0]
                    info.rate = (len(f.arrivals) - 1) / span if span > 0 else 0.0
                    info.delay = sum(f.delays) / len(f.delays)
                    info.max_delay = max(f.delays)
                out.append(info)
        return out

    def _prune(self, f: _Frame, now: float) -> None:
        edge = now - self.window
        while f.arrivals and f.arrivals[0] < edge:
            f.arrivals.popleft()
            f.delays.popleft()

    def clear(self) -> None:
        """Forget every frame."""
        with self._lock:
            self._frames.clear()
