"""The two graphs mirrored: zenros nodes and endpoints as rmw_zenoh liveliness tokens, rmw_zenoh
nodes and endpoints as zenros liveliness tokens, so ``ros2 node list`` shows zenros nodes and
``zenros node list`` shows ROS 2 nodes.

Every mirrored token is declared by the bridge's session and carries its session id, so the
bridge never mirrors (or bridges) it back. What it does not know stays out: an endpoint whose
type has no ROS 2 definition is not mirrored to rmw_zenoh (it has no hash), but every rmw_zenoh
endpoint is mirrored to zenros under its type name (``pkg/Name``), known or not.

- zenros -> rmw_zenoh: ``node`` -> ``NN`` (a node id per zenros node), ``pub``/``sub`` ->
  ``MP``/``MS`` with the QoS of the token's tag, ``srv``/``cli`` -> ``SS``/``SC``, ``act`` ->
  the three ``SS`` and two ``MP`` of an action server under ``<name>/_action/``, ``actc`` ->
  three ``SC`` and two ``MS``.
- rmw_zenoh -> zenros: ``NN`` -> ``node`` (host ``rmw_zenoh``, pid 0), ``MP``/``MS``/``SS``/
  ``SC`` -> ``pub``/``sub``/``srv``/``cli``, except an action's endpoints: its send_goal
  ``SS`` (``SC``) is the action server (client) ``act`` (``actc``), the rest are hidden, as
  ``ros2 topic list`` hides them.
"""

from __future__ import annotations

import itertools
import time
from typing import Any

import zenoh
from zenros.errors import ZenrosError
from zenros.names import Token, join
from zenros.qos import Durability as ZDurability
from zenros.qos import QoSProfile
from zenros.qos import Reliability as ZReliability
from zenros.ros2.rmw_zenoh import (
    Durability,
    Entity,
    EntityKind,
    Qos,
    Reliability,
    action_endpoints,
    type_part,
)
from zenros.ros2.typenames import dds_to_ros, ros_to_zenros, zenros_to_ros

from .host import BridgeHost

__all__ = ["GraphMirror"]

ACTION_HOST = "rmw_zenoh"  # the host field of a mirrored ROS 2 node's zenros token
_SEND_GOAL = "/_action/send_goal"
_KIND_TO_ROS = {"pub": EntityKind.PUBLISHER, "sub": EntityKind.SUBSCRIPTION,
                "srv": EntityKind.SERVICE, "cli": EntityKind.CLIENT}
_ROS_TO_KIND = {v: k for k, v in _KIND_TO_ROS.items()}
_SERVICE_QOS = Qos(depth=10)
_STATUS_QOS = Qos(depth=1, durability=Durability.TRANSIENT_LOCAL)


def qos_of_tag(tag: str) -> Qos:
    """rmw_zenoh's QoS for a zenros QoS tag (``rel+tl+1``)."""
    z = QoSProfile.from_tag(tag)
    return Qos(depth=z.depth,
               reliability=(Reliability.BEST_EFFORT if z.reliability is ZReliability.BEST_EFFORT
                            else Reliability.RELIABLE),
               durability=(Durability.TRANSIENT_LOCAL if z.durability is ZDurability.TRANSIENT_LOCAL
                           else Durability.VOLATILE))


def tag_of_qos(qos: Qos) -> str:
    """zenros's QoS tag for an rmw_zenoh QoS."""
    q = qos.normalized()
    return QoSProfile(
        depth=max(1, min(q.depth, 1000)),
        reliability=(ZReliability.BEST_EFFORT if q.reliability is Reliability.BEST_EFFORT
                     else ZReliability.RELIABLE),
        durability=(ZDurability.TRANSIENT_LOCAL if q.durability is Durability.TRANSIENT_LOCAL
                    else ZDurability.VOLATILE)).tag


class GraphMirror:
    def __init__(self, bridge: BridgeHost) -> None:
        self.bridge = bridge
        self.lv = bridge.session.liveliness()
        self._node_ids: dict[str, int] = {}
        self._next_node = itertools.count(1)  # 0 is the bridge node
        self._eids = itertools.count(1_000_000)  # apart from the bridge's own routes' ids
        self._out: dict[str, list[Any]] = {}  # zenros token key -> rmw_zenoh tokens
        self._in: dict[str, Any] = {}  # rmw_zenoh token key -> zenros token

    # ------------------------------------------------------------ zenros -> rmw_zenoh

    def _node(self, fqn: str) -> tuple[int, str, str]:
        if fqn not in self._node_ids:
            self._node_ids[fqn] = next(self._next_node)
        ns, _, name = fqn.rpartition("/")
        return self._node_ids[fqn], ns or "/", name

    def on_zenros(self, kind: zenoh.SampleKind, key: str, tok: Token) -> None:
        if kind == zenoh.SampleKind.DELETE:
            for t in self._out.pop(key, []):
                t.undeclare()
            return
        if key in self._out or (tok.kind != "node" and not self.bridge.wanted(tok.name)):
            return
        try:
            entities = self._entities_of(tok)
        except (ZenrosError, ValueError) as exc:  # no ROS 2 definition: no hash, no token
            self.bridge.problems(f"mirror {tok.type}", "not in the rmw_zenoh graph: %s %s (%s): "
                                 "%s", tok.kind, tok.name or tok.node, tok.type, exc)
            return
        self._out[key] = [self.lv.declare_token(e.token()) for e in entities]

    def _entities_of(self, tok: Token) -> list[Entity]:
        b = self.bridge
        nid, ns, name = self._node(tok.node)

        def ent(kind: EntityKind, topic: str, ros_type: str, qos: Qos) -> Entity:
            dds, h = type_part(ros_type)
            return Entity(b.domain, b.zid, nid, next(self._eids), kind, ns, name, topic=topic,
                          dds_type=dds, type_hash=h, qos=qos)

        if tok.kind == "node":
            return [Entity(b.domain, b.zid, nid, nid, EntityKind.NODE, ns, name)]
        if tok.kind in ("pub", "sub"):
            return [ent(_KIND_TO_ROS[tok.kind], tok.name, zenros_to_ros(tok.type),
                        qos_of_tag(tok.qos))]
        if tok.kind in ("srv", "cli"):
            return [ent(_KIND_TO_ROS[tok.kind], tok.name, zenros_to_ros(tok.type, "srv"),
                        _SERVICE_QOS)]
        if tok.kind in ("act", "actc"):
            server = tok.kind == "act"
            ends = action_endpoints(tok.name, zenros_to_ros(tok.type, "action"))
            srv_kind = EntityKind.SERVICE if server else EntityKind.CLIENT
            top_kind = EntityKind.PUBLISHER if server else EntityKind.SUBSCRIPTION
            return [ent(srv_kind, *ends[p], _SERVICE_QOS)
                    for p in ("send_goal", "cancel_goal", "get_result")] + [
                ent(top_kind, *ends["feedback"], Qos(depth=10)),
                ent(top_kind, *ends["status"], _STATUS_QOS)]
        return []

    # ------------------------------------------------------------ rmw_zenoh -> zenros

    def on_ros(self, kind: zenoh.SampleKind, key: str, ent: Entity) -> None:
        if kind == zenoh.SampleKind.DELETE:
            tok = self._in.pop(key, None)
            if tok is not None:
                tok.undeclare()
            return
        if key in self._in:
            return
        zkey = self._zenros_token(ent)
        if zkey is not None:
            self._in[key] = self.lv.declare_token(zkey)

    def _zenros_token(self, ent: Entity) -> str | None:
        ctx = self.bridge.context
        node = join(ent.namespace or "/", ent.node)
        if ent.kind is EntityKind.NODE:
            return ctx.keys.node_token(node, ctx.zid, ACTION_HOST, 0, time.time_ns())
        if not self.bridge.wanted(ent.topic.removesuffix(_SEND_GOAL)):
            return None
        try:
            ros_type = dds_to_ros(ent.dds_type)
            short = ros_to_zenros(ros_type)
        except ZenrosError:
            return None
        kind, name, qos = _ROS_TO_KIND[ent.kind], ent.topic, ""
        if "/_action/" in name:
            if not name.endswith(_SEND_GOAL) or ent.kind not in (EntityKind.SERVICE,
                                                                  EntityKind.CLIENT):
                return None  # an action's other endpoints: part of the action
            kind = "act" if ent.kind is EntityKind.SERVICE else "actc"
            name, short = name.removesuffix(_SEND_GOAL), short.removesuffix("_SendGoal")
        elif kind in ("pub", "sub"):
            qos = tag_of_qos(ent.qos)
        return ctx.keys.entity_token(kind, node, name, short, qos, ctx.zid, ctx.next_eid())

    def close(self) -> None:
        for toks in self._out.values():
            for t in toks:
                t.undeclare()
        for t in self._in.values():
            t.undeclare()
        self._out.clear()
        self._in.clear()
