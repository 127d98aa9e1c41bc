"""QoS events, as rclpy's ``event_callbacks``: matched, incompatible QoS, deadline missed,
liveliness changed and lost, message lost (lifespan).

``node.create_publisher(T, topic, qos, event_callbacks=PublisherEventCallbacks(...))`` and
``node.create_subscription(..., event_callbacks=SubscriptionEventCallbacks(...))`` take
rclpy's classes of those names; each callback gets rclpy's info (``total_count`` and
``total_count_change``...). Where the events come from (docs/runtime.md, "QoS events"):

- **matched**: the graph (liveliness tokens) gains or loses an endpoint of the other kind on
  the topic; ``total_count`` counts every match ever made, ``current_count`` those now.
- **incompatible QoS**: such an endpoint asks what the other does not offer (ROS 2's rules:
  best effort offered to a reliable request, volatile to transient local, a longer or no
  deadline or lease to a shorter one, automatic liveliness to manual). Zenoh still carries
  the samples, so zenros still delivers them; a ROS 2 (DDS) system would not connect the
  two, and the event says so. With ``use_default_callbacks`` and no callback, a warning.
- **deadline missed**: a publisher that has published once and then not within
  ``qos.deadline`` (offered), a subscription that has received once and then nothing within
  it (requested): one miss per period without a sample, from the last sample on.
- **liveliness**: a subscription's ``alive_count`` is its matched publishers that are alive:
  an AUTOMATIC one while its token stands (its process runs: a frozen or killed one leaves
  after its Zenoh lease), a MANUAL_BY_TOPIC one while its samples come within its
  ``liveliness_lease_duration`` (a lapse makes it not alive, the next sample alive again).
  A MANUAL_BY_TOPIC publisher that neither publishes nor calls ``assert_liveliness()``
  within its lease gets liveliness lost (``assert_liveliness()`` alone does not reach other
  processes: their subscriptions see samples only).
- **message lost**: a subscription drops a sample older than its publisher's ``lifespan``
  (its age from the sample's source timestamp), and counts it.

Event callbacks run on the thread that noticed (the graph's, the deadline timer's, the
receiving one) and must not block; an exception is logged, never raised into it. An entity
without ``event_callbacks`` costs nothing (no timer, no graph listener).
"""

from __future__ import annotations

import heapq
import itertools
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from enum import IntEnum
from typing import TYPE_CHECKING, Any

from .qos import Durability, Liveliness, QoSProfile, Reliability

if TYPE_CHECKING:
    from .graph import Graph
    from .names import Token

__all__ = [
    "PublisherEventCallbacks",
    "QoSLivelinessChangedInfo",
    "QoSLivelinessLostInfo",
    "QoSMessageLostInfo",
    "QoSOfferedDeadlineMissedInfo",
    "QoSOfferedIncompatibleQoSInfo",
    "QoSPolicyKind",
    "QoSPublisherMatchedInfo",
    "QoSRequestedDeadlineMissedInfo",
    "QoSRequestedIncompatibleQoSInfo",
    "QoSSubscriptionMatchedInfo",
    "SubscriptionEventCallbacks",
    "incompatible_policy",
]


class QoSPolicyKind(IntEnum):
    """rmw's policy kinds (``1 << n``), as rclpy's ``QoSPolicyKind``."""

    INVALID = 1 << 0
    DURABILITY = 1 << 1
    DEADLINE = 1 << 2
    LIVELINESS = 1 << 3
    RELIABILITY = 1 << 4
    HISTORY = 1 << 5
    LIFESPAN = 1 << 6
    DEPTH = 1 << 7
    LIVELINESS_LEASE_DURATION = 1 << 8
    AVOID_ROS_NAMESPACE_CONVENTIONS = 1 << 9


@dataclass(frozen=True)
class _Counted:
    total_count: int
    total_count_change: int


class QoSOfferedDeadlineMissedInfo(_Counted):
    """A publisher missed its deadline ``total_count`` times (``total_count_change`` since
    the last event)."""


class QoSRequestedDeadlineMissedInfo(_Counted):
    """A subscription went ``total_count`` deadlines without a sample."""


class QoSLivelinessLostInfo(_Counted):
    """A MANUAL_BY_TOPIC publisher let its lease pass unasserted ``total_count`` times."""


class QoSMessageLostInfo(_Counted):
    """A subscription dropped ``total_count`` samples (older than their lifespan)."""


@dataclass(frozen=True)
class _Incompatible:
    total_count: int
    total_count_change: int
    last_policy_kind: QoSPolicyKind


class QoSOfferedIncompatibleQoSInfo(_Incompatible):
    """Subscriptions requesting what this publisher does not offer."""


class QoSRequestedIncompatibleQoSInfo(_Incompatible):
    """Publishers not offering what this subscription requests."""


@dataclass(frozen=True)
class _Matched:
    total_count: int
    total_count_change: int
    current_count: int
    current_count_change: int


class QoSPublisherMatchedInfo(_Matched):
    """Subscriptions matched to this publisher: ever (``total_count``) and now."""


class QoSSubscriptionMatchedInfo(_Matched):
    """Publishers matched to this subscription: ever (``total_count``) and now."""


@dataclass(frozen=True)
class QoSLivelinessChangedInfo:
    """Matched publishers alive and not alive, and the changes since the last event."""

    alive_count: int
    not_alive_count: int
    alive_count_change: int
    not_alive_count_change: int


Callback = Callable[[Any], None] | None


@dataclass
class PublisherEventCallbacks:
    """rclpy's: what a publisher is told (``deadline``, ``liveliness`` lost,
    ``incompatible_qos``, ``matched``)."""

    deadline: Callback = None
    liveliness: Callback = None
    incompatible_qos: Callback = None
    matched: Callback = None
    use_default_callbacks: bool = True


@dataclass
class SubscriptionEventCallbacks:
    """rclpy's: what a subscription is told (``deadline``, ``liveliness`` changed,
    ``incompatible_qos``, ``matched``, ``message_lost``)."""

    deadline: Callback = None
    liveliness: Callback = None
    incompatible_qos: Callback = None
    matched: Callback = None
    message_lost: Callback = None
    use_default_callbacks: bool = True


def incompatible_policy(offered: QoSProfile, requested: QoSProfile) -> QoSPolicyKind | None:
    """The first policy where a publisher's ``offered`` QoS does not meet a subscription's
    ``requested`` one (ROS 2's request-offered rules), or None."""
    if offered.reliability == Reliability.BEST_EFFORT \
            and requested.reliability == Reliability.RELIABLE:
        return QoSPolicyKind.RELIABILITY
    if offered.durability == Durability.VOLATILE \
            and requested.durability == Durability.TRANSIENT_LOCAL:
        return QoSPolicyKind.DURABILITY
    if requested.deadline and not (offered.deadline and offered.deadline <= requested.deadline):
        return QoSPolicyKind.DEADLINE
    if offered.liveliness == Liveliness.AUTOMATIC \
            and requested.liveliness == Liveliness.MANUAL_BY_TOPIC:
        return QoSPolicyKind.LIVELINESS
    if requested.liveliness_lease_duration and not (
            offered.liveliness_lease_duration
            and offered.liveliness_lease_duration <= requested.liveliness_lease_duration):
        return QoSPolicyKind.LIVELINESS_LEASE_DURATION
    return None


class DeadlineTimer:
    """One thread (per process: `event_timer`) that calls ``due(now)`` of each scheduled
    entry when its time comes (a heap; an entry is scheduled again at what it returns)."""

    def __init__(self) -> None:
        self._heap: list[tuple[float, int, Callable[[float], float | None]]] = []
        self._cond = threading.Condition()
        self._seq = itertools.count()
        self._closed = False
        self._thread = threading.Thread(target=self._run, name="zenros-qos-events",
                                        daemon=True)
        self._thread.start()

    def schedule(self, at: float, due: Callable[[float], float | None]) -> None:
        """Call ``due(now)`` at monotonic time ``at``; it returns the next time, or None."""
        with self._cond:
            heapq.heappush(self._heap, (at, next(self._seq), due))
            self._cond.notify()

    def _run(self) -> None:
        while True:
            with self._cond:
                while not self._closed and (not self._heap
                                            or self._heap[0][0] > time.monotonic()):
                    wait = self._heap[0][0] - time.monotonic() if self._heap else None
                    self._cond.wait(wait)
                if self._closed:
                    return
                _, _, due = heapq.heappop(self._heap)
            now = time.monotonic()
            try:
                nxt = due(now)
            except Exception:
                logging.getLogger("zenros.qos_events").exception("QoS event timer entry")
                nxt = None
            if nxt is not None:
                self.schedule(nxt, due)

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self._cond.notify()
        if threading.current_thread() is not self._thread:
            self._thread.join(2.0)


_timer: DeadlineTimer | None = None
_timer_lock = threading.Lock()


def event_timer() -> DeadlineTimer:
    """The process's timer for deadlines and leases, started on first use."""
    global _timer
    with _timer_lock:
        if _timer is None:
            _timer = DeadlineTimer()
        return _timer


class _Deadline:
    """A deadline watched from the last sample: ``touch()`` on each; ``on_miss(count)``
    (misses so far) once per period without one."""

    def __init__(self, timer: DeadlineTimer, period: float,
                 on_miss: Callable[[int], None]) -> None:
        self.period = period
        self.on_miss = on_miss
        self.last: float | None = None
        self.missed = 0
        self.closed = False
        self._timer = timer
        self._scheduled = False
        self._lock = threading.Lock()

    def touch(self) -> None:
        now = time.monotonic()
        with self._lock:
            self.last = now
            if self._scheduled or self.closed:
                return
            self._scheduled = True
        self._timer.schedule(now + self.period, self._due)

    def _due(self, now: float) -> float | None:
        with self._lock:
            if self.closed or self.last is None:
                self._scheduled = False
                return None
            due = self.last + self.period
            if due > now:  # a sample came meanwhile: watch from it
                return due
            self.missed += 1
            self.last = now  # the next period runs from this miss
            missed = self.missed
        self.on_miss(missed)
        return now + self.period


@dataclass
class _Peer:
    qos: QoSProfile
    alive: bool = True
    last_sample: float = 0.0


class EntityEvents:
    """The events of one publisher or subscription (``kind`` "pub" or "sub") on ``topic``:
    follows the graph for the endpoints of the other kind, and the deadline, liveliness and
    lifespan of its own samples."""

    def __init__(self, kind: str, topic: str, qos: QoSProfile, own_eid: str,
                 callbacks: PublisherEventCallbacks | SubscriptionEventCallbacks,
                 graph: Graph, logger: logging.Logger,
                 timer: Callable[[], DeadlineTimer] = event_timer) -> None:
        self.kind = kind
        self.topic = topic
        self.qos = qos
        self.cb = callbacks
        self.logger = logger
        self._own = own_eid
        self._other = "sub" if kind == "pub" else "pub"
        self._lock = threading.RLock()
        self._peers: dict[str, _Peer] = {}  # by zid/eid
        self.matched_total = 0
        self.incompatible_total = 0
        self.lost_total = 0
        self.liveliness_lost_total = 0
        self._alive = 0
        self._not_alive = 0
        self.deadline: _Deadline | None = None
        self._lease: _Deadline | None = None
        if qos.deadline and callbacks.deadline is not None:
            self.deadline = _Deadline(timer(), qos.deadline, self._deadline_missed)
        if kind == "pub" and qos.liveliness == Liveliness.MANUAL_BY_TOPIC \
                and qos.liveliness_lease_duration and callbacks.liveliness is not None:
            self._lease = _Deadline(timer(), qos.liveliness_lease_duration, self._lease_lost)
            self._lease.touch()  # a manual publisher asserts from its creation
        self._timer = timer
        self._graph = graph
        self._unlisten = graph.add_listener(self._on_graph)
        for tok in (graph.subscribers(topic) if kind == "pub" else graph.publishers(topic)):
            self._on_graph("put", tok)

    # ------------------------------------------------------------------ samples

    def sample(self, source_zid: str = "", stamp_ns: Callable[[], int] | None = None) -> bool:
        """A sample published (pub) or received (sub) from session ``source_zid``;
        ``stamp_ns()`` its source time (Unix ns), read only when a publisher has a lifespan.
        False when it is to be dropped: older than its publisher's lifespan (message lost)."""
        if self.kind == "sub":
            peers = self._peers_of(source_zid)
            lifespan = max((p.qos.lifespan for p in peers), default=0.0)
            if lifespan and stamp_ns is not None:
                age = (time.time_ns() - stamp_ns()) / 1e9
                if age > lifespan:
                    self._message_lost()
                    return False
            self._asserted(peers)
        if self.deadline is not None:
            self.deadline.touch()
        if self._lease is not None:
            self._lease.touch()
        return True

    def assert_liveliness(self) -> None:
        if self._lease is not None:
            self._lease.touch()

    def _peers_of(self, zid: str) -> list[_Peer]:
        with self._lock:
            return [p for k, p in self._peers.items() if zid and k.startswith(zid + "/")]

    # ------------------------------------------------------------------ graph

    def _on_graph(self, event: str, tok: Token) -> None:
        if tok.kind != self._other or tok.name != self.topic:
            return
        key = f"{tok.zid}/{tok.eid}"
        if key == self._own:
            return
        with self._lock:
            known = key in self._peers
            if event == "put" and not known:
                peer = _Peer(QoSProfile.from_tag(tok.qos), last_sample=time.monotonic())
                self._peers[key] = peer
                self.matched_total += 1
                self._matched(+1)
                if self.kind == "sub":
                    self._liveliness(+1, 0)
                    self._watch_manual(key, peer)
                self._check_compatible(peer.qos)
            elif event == "delete" and known:
                peer = self._peers.pop(key)
                self._matched(-1)
                if self.kind == "sub":
                    self._liveliness(-1 if peer.alive else 0, 0 if peer.alive else -1)

    def _check_compatible(self, other: QoSProfile) -> None:
        offered, requested = (self.qos, other) if self.kind == "pub" else (other, self.qos)
        policy = incompatible_policy(offered, requested)
        if policy is None:
            return
        self.incompatible_total += 1
        info_cls = (QoSOfferedIncompatibleQoSInfo if self.kind == "pub"
                    else QoSRequestedIncompatibleQoSInfo)
        info = info_cls(self.incompatible_total, 1, policy)
        if self.cb.incompatible_qos is not None:
            self._call(self.cb.incompatible_qos, info)
        elif self.cb.use_default_callbacks:
            who = "subscription" if self.kind == "pub" else "publisher"
            what = "requesting" if self.kind == "pub" else "offering"
            self.logger.warning(
                "new %s discovered on topic %s, %s incompatible QoS (policy %s): a ROS 2 "
                "(DDS) system would not connect them; zenros still delivers", who,
                self.topic, what, policy.name)

    def _matched(self, change: int) -> None:
        if self.cb.matched is None:
            return
        current = len(self._peers)
        cls = QoSPublisherMatchedInfo if self.kind == "pub" else QoSSubscriptionMatchedInfo
        self._call(self.cb.matched, cls(self.matched_total, max(change, 0), current, change))

    # ------------------------------------------------------------------ liveliness

    def _liveliness(self, alive_change: int, not_alive_change: int) -> None:
        self._alive += alive_change
        self._not_alive += not_alive_change
        cb = self.cb.liveliness
        if cb is not None and (alive_change or not_alive_change):
            self._call(cb, QoSLivelinessChangedInfo(self._alive, self._not_alive,
                                                    alive_change, not_alive_change))

    def _watch_manual(self, key: str, peer: _Peer) -> None:
        """A MANUAL_BY_TOPIC publisher with a lease: not alive when its samples stop."""
        lease = peer.qos.liveliness_lease_duration
        if peer.qos.liveliness != Liveliness.MANUAL_BY_TOPIC or not lease \
                or self.cb.liveliness is None:
            return

        def due(now: float) -> float | None:
            with self._lock:
                if self._peers.get(key) is not peer:
                    return None
                if peer.alive and now - peer.last_sample >= lease:
                    peer.alive = False
                    self._liveliness(-1, +1)
                return max(now, peer.last_sample) + lease

        self._timer().schedule(time.monotonic() + lease, due)

    def _asserted(self, peers: list[_Peer]) -> None:
        now = time.monotonic()
        with self._lock:
            for p in peers:
                p.last_sample = now
                if not p.alive:
                    p.alive = True
                    self._liveliness(+1, -1)

    # ------------------------------------------------------------------ counted events

    def _deadline_missed(self, count: int) -> None:
        cls = (QoSOfferedDeadlineMissedInfo if self.kind == "pub"
               else QoSRequestedDeadlineMissedInfo)
        self._call(self.cb.deadline, cls(count, 1))

    def _lease_lost(self, count: int) -> None:
        self.liveliness_lost_total = count
        self._call(self.cb.liveliness, QoSLivelinessLostInfo(count, 1))

    def _message_lost(self) -> None:
        with self._lock:
            self.lost_total += 1
            total = self.lost_total
        cb = getattr(self.cb, "message_lost", None)
        if cb is not None:
            self._call(cb, QoSMessageLostInfo(total, 1))

    def _call(self, cb: Callback, info: Any) -> None:
        if cb is None:
            return
        try:
            cb(info)
        except Exception:
            self.logger.exception("QoS event callback on %s raised", self.topic)

    def close(self) -> None:
        self._unlisten()
        for d in (self.deadline, self._lease):
            if d is not None:
                d.closed = True
