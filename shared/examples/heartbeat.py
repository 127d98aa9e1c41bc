"""Heartbeats on a plain and a cached topic, and a monitor that counts which ones arrive."""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Callable
from typing import Any

from zenros import Node, run
from zenros.msgs.std_msgs import Int64
from zenros.qos import Durability, QoSProfile

__all__ = ["CACHED_TOPIC", "PLAIN_TOPIC", "REPORT_TAG", "Heartbeat", "SeqTracker"]

PLAIN_TOPIC = "heartbeat"  # reliable, volatile: what is published during an outage may be lost
CACHED_TOPIC = "heartbeat_cached"  # transient local: the publisher's cache refills the gaps
REPORT_TAG = "heartbeat_report"  # the monitor logs "heartbeat_report {json}" lines
MAX_TRACKED_HOLES = 100_000  # a bigger jump is counted as lost without remembering each number


class SeqTracker:
    """Counts a stream of sequence numbers: received, lost (holes), late, duplicate, gaps.

    A number above the highest seen opens a hole for every number skipped; a number that
    fills a hole later is counted as ``late`` (recovered), one seen before as ``duplicates``.
    ``lost`` is the holes still open. Arrival gaps are measured with ``clock`` (default
    `time.monotonic`, which all processes of a machine share). A 1 after higher numbers is a
    restarted publisher: the count starts again, and the open holes stay counted as lost.
    """

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self._clock = clock
        self._lock = threading.Lock()
        self.received = 0
        self.duplicates = 0
        self.late = 0
        self.restarts = 0
        self.first: int | None = None
        self.last: int | None = None
        self._holes: set[int] = set()
        self._lost_before = 0  # holes left open by earlier runs of the publisher, or untracked
        self.last_rx: float | None = None
        self.max_gap = 0.0
        self.max_gap_end: float | None = None

    @property
    def lost(self) -> int:
        return self._lost_before + len(self._holes)

    def add(self, seq: int) -> None:
        """Record the arrival of ``seq``, now."""
        now = self._clock()
        with self._lock:
            self._count(seq)
            if self.last_rx is not None and now - self.last_rx > self.max_gap:
                self.max_gap, self.max_gap_end = now - self.last_rx, now
            self.last_rx = now

    def _count(self, seq: int) -> None:
        self.received += 1
        if self.last is None or self.first is None:
            self.first = self.last = seq
            return
        if seq > self.last:
            skipped = seq - self.last - 1
            if skipped > MAX_TRACKED_HOLES:
                self._lost_before += skipped
            else:
                self._holes.update(range(self.last + 1, seq))
            self.last = seq
        elif seq in self._holes:
            self._holes.discard(seq)
            self.late += 1
        elif seq == 1 and self.last > 1:
            self.restarts += 1
            self._lost_before += len(self._holes)
            self._holes.clear()
            self.first = self.last = 1
        else:
            self.duplicates += 1

    def report(self) -> dict[str, Any]:
        """The counts as plain data (``first``/``last`` are None before the first arrival)."""
        with self._lock:
            return {
                "received": self.received, "first": self.first, "last": self.last,
                "lost": self.lost, "late": self.late, "duplicates": self.duplicates,
                "restarts": self.restarts, "max_gap": round(self.max_gap, 3),
                "max_gap_end": self.max_gap_end, "last_rx": self.last_rx,
            }


class Heartbeat(Node):
    """Publishes and/or watches heartbeats.

    Parameters:
        rate: heartbeats per second on ``heartbeat`` and ``heartbeat_cached``, both relative to
            the node's namespace (0: publish nothing).
        cache: how many heartbeats the cached topic keeps for late or reconnecting
            subscribers (the default covers 20 s at 50 Hz).
        watch: namespaces whose heartbeats to count, e.g. ``[robot1, robot2]``.
        report_period: seconds between two ``heartbeat_report`` log lines per watched topic.
    """

    node_name = "heartbeat"

    def setup(self) -> None:
        rate = float(self.declare_parameter("rate", 50.0))
        cache = int(self.declare_parameter("cache", 1000))
        watch: list[Any] = self.declare_parameter("watch", [])
        period = float(self.declare_parameter("report_period", 1.0))
        plain, cached = QoSProfile(), QoSProfile(depth=cache,
                                                 durability=Durability.TRANSIENT_LOCAL)
        self.seq = 0
        if rate > 0:
            self.plain_pub = self.create_publisher(Int64, PLAIN_TOPIC, plain)
            self.cached_pub = self.create_publisher(Int64, CACHED_TOPIC, cached)
            self.create_timer(1.0 / rate, self.on_tick)
        self.trackers: dict[str, SeqTracker] = {}
        for ns in watch:
            for name, qos in ((PLAIN_TOPIC, plain), (CACHED_TOPIC, cached)):
                topic = f"/{str(ns).strip('/')}/{name}" if str(ns).strip("/") else f"/{name}"
                tracker = SeqTracker()
                self.trackers[topic] = tracker
                self.create_subscription(Int64, topic, self._counter(tracker), qos)
        if self.trackers:
            self.create_timer(period, self.on_report)

    def on_tick(self) -> None:
        self.seq += 1
        msg = Int64(data=self.seq)
        self.plain_pub.publish(msg)
        self.cached_pub.publish(msg)

    def _counter(self, tracker: SeqTracker) -> Callable[[Int64], None]:
        def on_heartbeat(msg: Int64) -> None:
            tracker.add(msg.data)
        return on_heartbeat

    def on_report(self) -> None:
        for topic, tracker in self.trackers.items():
            self.logger.info("%s %s", REPORT_TAG, json.dumps({"topic": topic, **tracker.report()}))


if __name__ == "__main__":
    run(Heartbeat)
