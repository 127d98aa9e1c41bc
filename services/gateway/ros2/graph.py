"""ROS 2 nodes in the zenros graph: what each DDS participant says on ``ros_discovery_info``
(rmw_dds_common/msg/ParticipantEntitiesInfo: its nodes, with their readers' and writers'
GIDs) becomes one zenros node token per ROS 2 node, gone when the node or its participant is."""

from __future__ import annotations

import os
import time
import uuid
from typing import Any

from cyclonedds._clayer import ddspy_take
from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsParticipant
from cyclonedds.core import InstanceState, Policy, Qos, SampleState, ViewState
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from zenros.errors import CodecError, UnknownTypeError
from zenros.ros2.cdr import cdr_codec_for_name
from zenros.ros2.registry import definition, register_interface

from .ddstypes import dds_type
from .host import BridgeHost

__all__ = ["RosNodes"]

_ANY = SampleState.Any | ViewState.Any | InstanceState.Any
_GONE_KEPT = 1024  # ended participants remembered, to drop their late announcements
_INFO = "rmw_dds_common/msg/ParticipantEntitiesInfo"
_INTERFACES = {  # rmw_dds_common 4.0 (Kilted; Jazzy's is the same): GIDs of 16 bytes
    "rmw_dds_common/msg/Gid": "char[16] data",
    "rmw_dds_common/msg/NodeEntitiesInfo":
        "string<=256 node_namespace\nstring<=256 node_name\nGid[] reader_gid_seq\n"
        "Gid[] writer_gid_seq",
    _INFO: "Gid gid\nNodeEntitiesInfo[] node_entities_info_seq",
}


def _register() -> None:
    try:
        definition(_INFO)
    except UnknownTypeError:
        for name, text in _INTERFACES.items():
            register_interface(name, text)


def _fqn(ns: str, name: str) -> str:
    ns = ns.rstrip("/")
    return f"{ns}/{name}" if ns.startswith("/") else f"/{ns}/{name}".replace("//", "/")


class RosNodes:
    """Folds ``ros_discovery_info`` into node tokens (call `poll` from the bridge's worker)."""

    def __init__(self, bridge: BridgeHost) -> None:
        _register()
        self.bridge = bridge
        self.codec = cdr_codec_for_name(_INFO)
        topic = Topic(bridge.participant, "ros_discovery_info", dds_type(_INFO))
        self.reader = DataReader(bridge.participant, topic, qos=Qos(
            Policy.Reliability.Reliable(100_000_000), Policy.Durability.TransientLocal,
            Policy.History.KeepLast(100), Policy.IgnoreLocal.Participant))
        self.participants = BuiltinDataReader(bridge.participant, BuiltinTopicDcpsParticipant)
        self.by_participant: dict[uuid.UUID, dict[str, Any]] = {}  # -> node fqn -> token
        self.writers: dict[uuid.UUID, str] = {}  # writer GID -> node fqn
        self.gone: dict[uuid.UUID, None] = {}  # participants seen to end, oldest first
        self._start = time.time_ns()

    def node_of_writer(self, key: uuid.UUID) -> str:
        return self.writers.get(key, "")

    def nodes(self) -> list[str]:
        return sorted(n for nodes in self.by_participant.values() for n in nodes)

    def poll(self) -> None:
        """Participants' announcements first, then which participants went: a participant's
        last announcement and its end can wait in the two readers together (a busy box), and
        an announcement taken after its participant's end would bring its nodes back for
        good. One that comes from a participant already gone is dropped."""
        self._take_announcements()
        for p in self.participants.take(64):
            if p.sample_info.instance_state == InstanceState.Alive:
                self.gone.pop(p.key, None)
            else:
                self.gone[p.key] = None
                while len(self.gone) > _GONE_KEPT:
                    del self.gone[next(iter(self.gone))]
                self._set(p.key, {})

    def _take_announcements(self) -> None:
        batch = ddspy_take(self.reader._ref, _ANY, 64)
        if isinstance(batch, int):
            return
        for data, info in batch:
            if not info.valid_data:
                continue
            try:
                msg: Any = self.codec.decode(data)
            except CodecError as exc:
                self.bridge.bad_sample("ros_discovery_info", str(info.publication_handle), exc)
                continue
            part = uuid.UUID(bytes=bytes(msg.gid.data))
            if part == self.bridge.guid or part in self.gone:
                continue
            nodes: dict[str, list[uuid.UUID]] = {}
            for n in msg.node_entities_info_seq:
                nodes[_fqn(n.node_namespace, n.node_name)] = [
                    uuid.UUID(bytes=bytes(g.data)) for g in n.writer_gid_seq]
            self._set(part, nodes)

    def _set(self, part: uuid.UUID, nodes: dict[str, list[uuid.UUID]]) -> None:
        old = self.by_participant.pop(part, {})
        ctx = self.bridge.context
        new: dict[str, Any] = {}
        for fqn, writers in nodes.items():
            for w in writers:
                self.writers[w] = fqn
            if fqn in old:
                new[fqn] = old.pop(fqn)
            else:
                new[fqn] = ctx.session.liveliness().declare_token(ctx.keys.node_token(
                    fqn, ctx.zid, "ros2-dds", os.getpid(), self._start))
                self.bridge.logger.info("ROS 2 node %s joined", fqn)
        for fqn, token in old.items():
            token.undeclare()
            self.bridge.logger.info("ROS 2 node %s left", fqn)
        if new:
            self.by_participant[part] = new

    def close(self) -> None:
        for nodes in self.by_participant.values():
            for token in nodes.values():
                token.undeclare()
        self.by_participant.clear()
