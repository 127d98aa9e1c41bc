"""An rmw_zenoh participant for the tests, built from parts zenros did not write.

zenoh-ros2-sdk 0.1.8 has publishers, subscribers, service clients and servers but no actions
and no transient-local publisher (its TRANSIENT_LOCAL publisher has no cache), so this peer
speaks rmw_zenoh's protocol on a raw Zenoh session, the way rmw_zenoh_cpp 0.6 declares it
(rmw_client_data.cpp, rmw_service_data.cpp, rmw_publisher_data.cpp):

- keys and liveliness tokens: the SDK's ``keyexpr`` module and entities;
- type hashes: the ``hashes`` of the ROS 2 wheels' ``share/<pkg>/<kind>/<Name>.json``;
- payloads: ``rclpy.serialization`` with the wheels' message classes;
- attachments: the SDK's ``Attachment``;
- transient local: a zenoh-ext advanced publisher with a cache and publisher detection, and an
  advanced subscriber with history, as rmw_zenoh_cpp configures them.

Only the Zenoh session comes from zenros (`zenros.session.open_session`: loopback, scouting
off); nothing of zenros's ROS 2 code is used.
"""

from __future__ import annotations

import itertools
import os
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import zenoh
from zenoh import ext as zext
from zenoh_ros2_sdk.attachment import Attachment
from zenoh_ros2_sdk.entity import EndpointEntity, EntityKind, NodeEntity
from zenoh_ros2_sdk.keyexpr import (
    endpoint_liveliness_keyexpr,
    node_liveliness_keyexpr,
    topic_keyexpr,
)
from zenros.session import SessionOptions, open_session

# the wheels' hashes and classes, as the CDR reference tests read them (one module, not two)
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "unit" / "ros2"))
from rosref import ros_class, wheel_hash

CDR = zenoh.Encoding("application/cdr")
SERVICE_QOS = "::,10:,:,:,,"  # reliable, volatile, keep-last 10 (rmw's services default)
STATUS_QOS = ":1:,1:,:,:,,"  # rcl_action's status: transient local, keep-last 1


def dds_name(ros_type: str) -> str:
    pkg, kind, name = ros_type.split("/")
    return f"{pkg}::{kind}::dds_::{name}_"


def serialize(msg: Any) -> bytes:
    from rclpy.serialization import serialize_message
    data: bytes = serialize_message(msg)
    return data


def deserialize(data: bytes, ros_type: str) -> Any:
    from rclpy.serialization import deserialize_message
    return deserialize_message(data, ros_class(ros_type))


class RmwPeer:
    """One rmw_zenoh node (``node``) on its own Zenoh session."""

    def __init__(self, router: str, domain: int, node: str = "rmw_peer") -> None:
        self.session = open_session(SessionOptions(connect=[router]))
        self.domain = domain
        self.zid = str(self.session.info.zid())
        self.node = NodeEntity(domain, self.zid, 0, node)
        self._eids = itertools.count(1)
        self._closers: list[Any] = [self.session.liveliness().declare_token(
            node_liveliness_keyexpr(self.node))]

    def key(self, name: str, ros_type: str) -> str:
        return topic_keyexpr(self.domain, name, dds_name(ros_type), wheel_hash(ros_type))

    def token(self, kind: EntityKind, name: str, ros_type: str, qos: str = SERVICE_QOS) -> bytes:
        """Declare an endpoint's token; its 16-byte GID (any unique value does)."""
        ep = EndpointEntity(self.node, next(self._eids), kind, name, dds_name(ros_type),
                            wheel_hash(ros_type), qos)
        self._closers.append(self.session.liveliness().declare_token(
            endpoint_liveliness_keyexpr(ep)))
        return os.urandom(16)

    # ------------------------------------------------------------ services

    def client(self, name: str, srv_type: str) -> PeerClient:
        gid = self.token(EntityKind.CLIENT, name, srv_type)
        return PeerClient(self.session, self.key(name, srv_type), gid)

    def serve(self, name: str, srv_type: str, handler: Callable[[bytes], bytes | None],
              *, echo: bool = True) -> None:
        """A complete queryable: ``handler(request CDR) -> response CDR`` (None: no reply);
        the reply echoes the request's sequence number and GID (``echo=False``: it does not,
        to test that the caller checks)."""
        self.token(EntityKind.SERVICE, name, srv_type)

        def on_query(query: zenoh.Query) -> None:
            att = Attachment.from_bytes(query.attachment.to_bytes())
            payload = query.payload.to_bytes() if query.payload is not None else b""

            def answer() -> None:
                try:
                    out = handler(payload)
                    if out is not None:
                        seq = att.sequence_id if echo else att.sequence_id + 1000
                        query.reply(query.key_expr, out, encoding=CDR, attachment=Attachment(
                            seq, time.time_ns(), att.gid).to_bytes())
                finally:
                    query.drop()
            threading.Thread(target=answer, daemon=True).start()  # get_result may wait

        self._closers.append(self.session.declare_queryable(
            self.key(name, srv_type), on_query, complete=True))

    # ------------------------------------------------------------ topics

    def publisher(self, name: str, ros_type: str, *, latched: bool = False,
                  depth: int = 10) -> PeerPublisher:
        qos = f":1:,{depth}:,:,:,," if latched else f"::,{depth}:,:,:,,"
        gid = self.token(EntityKind.PUBLISHER, name, ros_type, qos)
        key = self.key(name, ros_type)
        if latched:
            pub: Any = zext.declare_advanced_publisher(
                self.session, key, encoding=CDR,
                cache=zext.CacheConfig(max_samples=depth),
                sample_miss_detection=zext.MissDetectionConfig(heartbeat=None,
                                                                sporadic_heartbeat=0.5),
                publisher_detection=True)
        else:
            pub = self.session.declare_publisher(key, encoding=CDR)
        self._closers.append(pub)
        return PeerPublisher(pub, gid)

    def subscribe(self, name: str, ros_type: str, callback: Callable[[Any], None], *,
                  latched: bool = False, depth: int = 10) -> None:
        qos = f":1:,{depth}:,:,:,," if latched else f"::,{depth}:,:,:,,"
        self.token(EntityKind.SUBSCRIPTION, name, ros_type, qos)
        key = self.key(name, ros_type)

        def on_sample(sample: zenoh.Sample) -> None:
            callback(deserialize(sample.payload.to_bytes(), ros_type))

        if latched:
            sub: Any = zext.declare_advanced_subscriber(
                self.session, key, on_sample,
                history=zext.HistoryConfig(detect_late_publishers=True, max_samples=depth),
                recovery=zext.RecoveryConfig(heartbeat=True), subscriber_detection=True)
        else:
            sub = self.session.declare_subscriber(key, on_sample)
        self._closers.append(sub)

    def close(self) -> None:
        for c in reversed(self._closers):
            c.undeclare()
        self._closers.clear()
        self.session.close()  # type: ignore[no-untyped-call]


class PeerPublisher:
    def __init__(self, pub: Any, gid: bytes) -> None:
        self.pub = pub
        self.gid = gid
        self.seq = itertools.count(1)

    def publish(self, msg: Any) -> None:
        self.pub.put(serialize(msg), attachment=Attachment(
            next(self.seq), time.time_ns(), self.gid).to_bytes())


class PeerClient:
    """Calls as rmw_zenoh's client does: target ALL_COMPLETE, no consolidation, the
    attachment; returns the response and the reply's attachment."""

    def __init__(self, session: zenoh.Session, key: str, gid: bytes) -> None:
        self.session = session
        self.key = key
        self.gid = gid
        self.seq = itertools.count(1)

    def call(self, request: Any, response_type: str,
             timeout: float = 10.0) -> tuple[Any, Attachment, Attachment]:
        sent = Attachment(next(self.seq), time.time_ns(), self.gid)
        replies = self.session.get(
            self.key, payload=serialize(request), encoding=CDR, attachment=sent.to_bytes(),
            target=zenoh.QueryTarget.ALL_COMPLETE, consolidation=zenoh.ConsolidationMode.NONE,
            timeout=timeout)
        for reply in replies:
            if reply.ok is None:
                raise RuntimeError(f"{self.key}: error reply "
                                   f"{reply.err.payload.to_bytes()!r}")  # type: ignore[union-attr]
            got = Attachment.from_bytes(reply.ok.attachment.to_bytes())  # type: ignore[union-attr]
            return deserialize(reply.ok.payload.to_bytes(), response_type), sent, got
        raise TimeoutError(f"{self.key}: no reply")
