"""One bridged topic each way: a DDS reader republished as a zenros publisher (`Inbound`),
and a zenros subscriber written by a DDS writer (`Outbound`).

Samples stay bytes on the DDS side: cyclonedds hands over the serialized CDR and takes it
back (``ddspy_take``/``ddspy_write``), and zenros's compiled codec converts it; the
``IdlStruct`` types are only the topics' type descriptions (see docs/ros2.md, "DDS").
"""

from __future__ import annotations

from typing import Any

import zenoh
import zenoh.ext as zext
from cyclonedds._clayer import ddspy_take, ddspy_write
from cyclonedds.core import InstanceState, Listener, SampleState, ViewState
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from zenros.codec import codec_for
from zenros.errors import CodecError
from zenros.message import Message
from zenros.qos import QoSProfile
from zenros.ros2.cdr import cdr_codec
from zenros.ros2.registry import ros_name_of
from zenros.ros2.typehash import type_hash

from .ddstypes import dds_type
from .host import BridgeHost
from .qos import dds_qos

__all__ = ["Inbound", "Outbound", "dds_topic", "take_valid"]

_ANY = SampleState.Any | ViewState.Any | InstanceState.Any
_BATCH = 64


def take_valid(reader: Any) -> list[tuple[bytes, Any]]:
    """Every sample waiting in ``reader`` that has data, as (CDR bytes, sample info); none
    once the reader is being deleted. Samples without data (a writer left) are dropped."""
    out: list[tuple[bytes, Any]] = []
    while True:
        try:
            batch = ddspy_take(reader._ref, _ANY, _BATCH)
        except Exception:  # noqa: BLE001 the reader is being deleted
            return out
        if isinstance(batch, int):
            return out
        out.extend((data, info) for data, info in batch if info.valid_data)
        if len(batch) < _BATCH:
            return out


def dds_topic(bridge: BridgeHost, name: str, ros_type: str) -> Topic[Any]:
    """The bridge's (cached) DDS topic ``rt/<name>`` of one ROS 2 type."""
    key = (name, ros_type)
    topic = bridge.dds_topics.get(key)
    if topic is None:
        topic = Topic(bridge.participant, "rt" + name, dds_type(ros_type))
        bridge.dds_topics[key] = topic
    return topic


class Inbound:
    """A ROS 2 topic (DDS writers elsewhere) republished in zenros under its ROS name."""

    def __init__(self, bridge: BridgeHost, name: str, cls: type[Message],
                 qos: QoSProfile) -> None:
        self.bridge = bridge
        self.name = name
        self.qos = qos
        self.cdr = cdr_codec(cls)
        ros_type = ros_name_of(cls)
        self.pub = bridge.create_publisher(cls, name, qos)
        self.forwarded = 0
        self.reader = DataReader(bridge.participant, dds_topic(bridge, name, ros_type),
                                 qos=dds_qos(qos, type_hash(ros_type), writer=False),
                                 listener=Listener(on_data_available=self._on_data))  # type: ignore[no-untyped-call]
        self._on_data(self.reader)  # a transient-local backlog may be there already

    def _on_data(self, reader: Any) -> None:
        for data, info in take_valid(reader):
            try:
                msg = self.cdr.decode(data)
            except CodecError as exc:
                sender = str(info.publication_handle)
                self.bridge.bad_sample(self.name, self.bridge.writer_name(info.publication_handle)
                                       or sender, exc)
                continue
            self.pub.publish(msg)
            self.forwarded += 1

    def close(self) -> None:
        self.reader.set_listener(None)
        self.reader.__del__()  # deletes the DDS entity now, not when garbage collected
        self.bridge.destroy(self.pub)


class Outbound:
    """A zenros topic (publishers in other sessions) written to DDS as ``rt/<name>``."""

    def __init__(self, bridge: BridgeHost, name: str, cls: type[Message],
                 qos: QoSProfile) -> None:
        self.bridge = bridge
        self.name = name
        self.qos = qos
        self.native = codec_for(cls)
        self.cdr = cdr_codec(cls)
        ros_type = ros_name_of(cls)
        self.forwarded = 0
        self.writer = DataWriter(bridge.participant, dds_topic(bridge, name, ros_type),
                                 qos=dds_qos(qos, type_hash(ros_type), writer=True))
        ctx = bridge.context
        self.sub_token = ctx.session.liveliness().declare_token(ctx.keys.entity_token(
            "sub", bridge.fqn, name, self.native.type_name, qos.tag, ctx.zid, ctx.next_eid()))
        key = ctx.keys.topic(name)
        self.sub: Any
        if qos.latched:
            self.sub = zext.declare_advanced_subscriber(
                ctx.session, key, self._on_sample, allowed_origin=zenoh.Locality.REMOTE,
                history=zext.HistoryConfig(detect_late_publishers=True, max_samples=qos.depth),
                recovery=zext.RecoveryConfig(heartbeat=True, periodic_queries=None),
                subscriber_detection=True)
        else:
            self.sub = ctx.session.declare_subscriber(key, self._on_sample,
                                                      allowed_origin=zenoh.Locality.REMOTE)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        ts = sample.timestamp
        sender = str(ts.get_id()) if ts is not None else "unknown"
        if sender == self.bridge.zid:  # this session's own (latched history): never back
            return
        try:
            data = self.cdr.encode(self.native.decode(sample.payload.to_bytes()))
        except CodecError as exc:
            self.bridge.bad_sample(self.name, f"session {sender}", exc)
            return
        pad = -len(data) & 3
        try:
            ddspy_write(self.writer._ref, data + bytes(pad) if pad else data)
        except Exception as exc:  # noqa: BLE001 the writer is being deleted
            self.bridge.problems(f"write {self.name}", "cannot write %s to DDS: %s",
                                 self.name, exc)
            return
        self.forwarded += 1

    def close(self) -> None:
        self.sub.undeclare()
        self.sub_token.undeclare()  # type: ignore[no-untyped-call]
        self.writer.__del__()
