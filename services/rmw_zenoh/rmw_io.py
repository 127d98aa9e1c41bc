"""rmw_zenoh's side of the wire, as rmw_zenoh_cpp 0.6 declares it (rmw_publisher_data.cpp,
rmw_subscription_data.cpp, rmw_client_data.cpp, rmw_service_data.cpp).

- Publishers: a transient-local one is an advanced publisher with a cache of ``depth`` samples,
  publisher detection and (when reliable) sporadic heartbeats every 0.5 s for sample miss
  detection; a volatile one a plain publisher. Every sample carries the 33-byte attachment
  (sequence number from 1, source timestamp, the publisher's GID).
- Subscribers: a transient-local one is an advanced subscriber with history (late publishers
  detected, ``depth`` samples) and, when reliable, heartbeat recovery; a volatile one plain.
- Clients: a query with target ALL_COMPLETE, no consolidation, the attachment; the reply must
  echo the request's sequence number and GID (`Requester.check_echo`).
- Servers: a complete queryable; the reply echoes the request's sequence number and GID with a
  new source timestamp (`reply_echo`).
"""

from __future__ import annotations

import itertools
import threading
import time
from collections.abc import Callable
from typing import Any

import zenoh
from zenoh import ext as zext
from zenros.ros2.rmw_zenoh import Attachment, Durability, Qos, Reliability, RmwZenohError

__all__ = ["CDR", "Requester", "RmwPublisher", "declare_rmw_subscriber", "reply_echo"]

CDR = zenoh.Encoding("application/cdr")
SAMPLE_MISS_HEARTBEAT = 0.5  # s, rmw_zenoh's SAMPLE_MISS_DETECTION_HEARTBEAT_PERIOD (500 ms)


class RmwPublisher:
    """A publisher on an rmw_zenoh data key: each ``put`` carries the attachment."""

    def __init__(self, session: zenoh.Session, key: str, qos: Qos, gid: bytes) -> None:
        self.gid = gid
        self._seq = itertools.count(1)
        self._lock = threading.Lock()
        self._closed = False
        reliable = qos.reliability is not Reliability.BEST_EFFORT
        cc = zenoh.CongestionControl.BLOCK if reliable else zenoh.CongestionControl.DROP
        self.latched = qos.durability is Durability.TRANSIENT_LOCAL
        if self.latched:
            self._pub: Any = zext.declare_advanced_publisher(
                session, key, encoding=CDR, congestion_control=cc,
                cache=zext.CacheConfig(max_samples=max(1, qos.depth)),
                sample_miss_detection=(zext.MissDetectionConfig(
                    heartbeat=None, sporadic_heartbeat=SAMPLE_MISS_HEARTBEAT) if reliable else None),
                publisher_detection=True,
            )
        else:
            self._pub = session.declare_publisher(key, encoding=CDR, congestion_control=cc,
                                                  allowed_destination=zenoh.Locality.REMOTE)

    def put(self, data: bytes) -> None:
        """Send ``data``; after `close`, nothing (a sample racing the route's removal)."""
        with self._lock:  # sequence numbers in the order the samples leave
            if self._closed:
                return
            att = Attachment(next(self._seq), time.time_ns(), self.gid).encode()
            self._pub.put(data, attachment=att)

    def close(self) -> None:
        # Under the lock: zenoh-python refuses to undeclare a publisher while another thread
        # is in its put ("RuntimeError: Already borrowed").
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self._pub.undeclare()


def declare_rmw_subscriber(session: zenoh.Session, key: str, qos: Qos,
                           callback: Callable[[zenoh.Sample], None]) -> Any:
    """A subscriber on an rmw_zenoh data key, remote samples only (the bridge's own never come
    back); transient local: an advanced subscriber that fetches the publishers' caches."""
    if qos.durability is Durability.TRANSIENT_LOCAL:
        reliable = qos.reliability is not Reliability.BEST_EFFORT
        return zext.declare_advanced_subscriber(
            session, key, callback, allowed_origin=zenoh.Locality.REMOTE,
            history=zext.HistoryConfig(detect_late_publishers=True, max_samples=max(1, qos.depth)),
            recovery=(zext.RecoveryConfig(heartbeat=True, periodic_queries=None) if reliable
                      else None),
            subscriber_detection=True,
        )
    return session.declare_subscriber(key, callback, allowed_origin=zenoh.Locality.REMOTE)


def reply_echo(query: zenoh.Query, data: bytes, request: Attachment) -> None:
    """Reply to an rmw_zenoh request with the request's sequence number and GID, then finalize
    the query (Zenoh sends the replies of a query when it is dropped)."""
    try:
        query.reply(query.key_expr, data, encoding=CDR, attachment=Attachment(
            request.sequence_number, time.time_ns(), request.gid).encode())
    finally:
        query.drop()  # type: ignore[no-untyped-call]


def reply_error(query: zenoh.Query, message: str) -> None:
    try:
        query.reply_err(message)
    finally:
        query.drop()  # type: ignore[no-untyped-call]


def request_attachment(query: zenoh.Query) -> tuple[Attachment, bytes]:
    """The attachment and payload of an rmw_zenoh request; raises `RmwZenohError`."""
    if query.attachment is None:
        raise RmwZenohError("request without an attachment")
    att = Attachment.decode(query.attachment.to_bytes())
    if query.payload is None:
        raise RmwZenohError("request without a payload")
    return att, query.payload.to_bytes()


class Requester:
    """An rmw_zenoh service client: queries with the attachment, checks the echo."""

    def __init__(self, session: zenoh.Session, key: str, gid: bytes) -> None:
        self.session = session
        self.key = key
        self.gid = gid
        self._seq = itertools.count(1)
        self._lock = threading.Lock()

    def call(self, data: bytes, timeout: float,
             done: Callable[[bytes | None, str], None]) -> None:
        """Send one request; ``done(payload, "")`` with the reply's CDR bytes, or
        ``done(None, why)``, runs once on a Zenoh thread (it must not call Zenoh there)."""
        with self._lock:
            att = Attachment(next(self._seq), time.time_ns(), self.gid)
        state = {"called": False}
        lock = threading.Lock()

        def once(payload: bytes | None, why: str) -> None:
            with lock:
                if state["called"]:
                    return
                state["called"] = True
            done(payload, why)

        def on_reply(reply: zenoh.Reply) -> None:
            if reply.ok is None:
                err = reply.err
                once(None, err.payload.to_bytes().decode("utf-8", "replace") if err else "error")
                return
            try:
                self.check_echo(reply.ok, att)
            except RmwZenohError as exc:
                once(None, str(exc))
                return
            once(reply.ok.payload.to_bytes(), "")

        self.session.get(
            self.key, zenoh.handlers.Callback(on_reply, lambda: once(None, "no reply"),
                                              indirect=False),
            payload=data, encoding=CDR, attachment=att.encode(),
            target=zenoh.QueryTarget.ALL_COMPLETE, consolidation=zenoh.ConsolidationMode.NONE,
            timeout=timeout, allowed_destination=zenoh.Locality.REMOTE)

    def check_echo(self, sample: zenoh.Sample, sent: Attachment) -> Attachment:
        """The reply's attachment, checked: it echoes ``sent``'s sequence number and GID."""
        if sample.attachment is None:
            raise RmwZenohError(f"{self.key}: reply without an attachment")
        got = Attachment.decode(sample.attachment.to_bytes())
        if got.sequence_number != sent.sequence_number or got.gid != sent.gid:
            raise RmwZenohError(
                f"{self.key}: the reply does not echo the request (sequence number "
                f"{got.sequence_number}, GID {got.gid.hex()}; sent {sent.sequence_number}, "
                f"{sent.gid.hex()})")
        return got
