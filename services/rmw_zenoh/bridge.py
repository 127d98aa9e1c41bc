"""Mirror zenros topics, services and actions into rmw_zenoh's layout and ROS 2's into zenros.

One Zenoh session (the node's) speaks both layouts. Loops are cut twice: entities whose
token carries the bridge's own session id are never bridged, and every raw subscriber the
bridge declares takes only remote samples (``Locality.REMOTE``), so what it put one way
never comes back the other.

- zenros -> ROS 2: for each zenros topic with a publisher elsewhere and a ROS 2 definition,
  a publisher on the rmw_zenoh data key (CDR, with the 33-byte attachment; latched topics
  transient local: `rmw_io`) and its ``MP`` token; for each zenros service, a complete
  queryable and its ``SS`` token, which calls the zenros service and replies echoing the
  request's sequence number and GID; for each zenros action server, its three services and
  two topics under ``<name>/_action/`` (`actions.ActionOut`).
- ROS 2 -> zenros: for each ``MP`` token of another session, a zenros publisher under the
  ROS name (the bridge node shows in ``zenros node list`` as its publisher); for each ``SS``
  token, a zenros service (`service_in`) or, for an action's send_goal, a zenros action
  server (`actions.ActionIn`).

Bad input: a sample that does not decode is dropped, counted, and logged once per sender; a
type zenros does not know or whose hash differs is logged once per topic and skipped.
"""

from __future__ import annotations

import itertools
import queue
import threading
from collections import defaultdict
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import zenoh
from zenoh import ext as zext
from zenros.codec import codec_for
from zenros.errors import CodecError, UnknownTypeError, ZenrosError
from zenros.log import LogOnce
from zenros.message import Message
from zenros.node import Node
from zenros.qos import Durability as ZDurability
from zenros.qos import QoSProfile
from zenros.qos import Reliability as ZReliability
from zenros.registry import lookup_action, lookup_service, lookup_type
from zenros.ros2.cdr import cdr_codec
from zenros.ros2.domain import NameFilter
from zenros.ros2.registry import ros_name_of, zenros_class_of
from zenros.ros2.rmw_zenoh import (
    Attachment,
    Durability,
    Entity,
    EntityKind,
    Qos,
    Reliability,
    RmwZenohError,
    data_key,
    type_part,
)
from zenros.ros2.typenames import dds_to_ros

from .actions import ActionIn, ActionOut
from .graph_mirror import GraphMirror
from .params import RmwZenohParameters
from .rmw_io import (
    RmwPublisher,
    declare_rmw_subscriber,
    reply_echo,
    reply_error,
    request_attachment,
)
from .service_in import ServiceIn

__all__ = ["RmwZenohBridge"]

ACTION_SEND_GOAL = "/_action/send_goal"


class RmwZenohBridge(Node):
    """Parameters: `RmwZenohParameters` (``domain_id``, ``allow`` and ``deny`` regular
    expressions on names, deny winning, what to bridge, the call timeouts)."""

    node_name = "rmw_zenoh_bridge"

    def setup(self) -> None:
        p = self.declare_parameters(RmwZenohParameters)
        self.domain = p.domain_id
        self.name_filter = NameFilter(p)
        self.bridge_services = p.services
        self.bridge_actions = p.actions
        self.mirror_graph = p.mirror_graph
        self.call_timeout = p.call_timeout
        self.result_timeout = p.result_timeout
        ctx = self.context
        self.session = ctx.session
        self.zid = str(ctx.zid)
        self.problems = LogOnce(self.logger)
        self._eids = itertools.count(1)
        self._graph_lock = threading.Lock()
        self._events: queue.Queue[tuple[str, zenoh.SampleKind, str] | None] = queue.Queue()
        self._zenros: dict[tuple[str, str], set[str]] = defaultdict(set)  # (kind, name) -> tokens
        self._ros: dict[tuple[str, str], set[str]] = defaultdict(set)
        self.outbound: dict[str, _Outbound] = {}
        self.inbound: dict[tuple[str, str], _Inbound] = {}
        self.services: dict[str, _ServiceOut] = {}
        self.services_in: dict[str, ServiceIn] = {}
        self.actions: dict[str, ActionOut] = {}
        self.actions_in: dict[str, ActionIn] = {}
        self.pool = ThreadPoolExecutor(4, thread_name_prefix="rmw-zenoh-srv")
        self.on_close(lambda: self.pool.shutdown(wait=False, cancel_futures=True))
        self.mirror = GraphMirror(self)
        self._node_entity = Entity(self.domain, self.zid, 0, 0, EntityKind.NODE,
                                   self.namespace, self.name)
        lv = self.session.liveliness()
        self._node_token = lv.declare_token(self._node_entity.token())
        self.on_close(self._node_token.undeclare)
        self._worker = threading.Thread(target=self._run, name="rmw-zenoh-bridge", daemon=True)
        self._worker.start()
        self.on_close(self._stop_worker)
        self._lv_zenros = lv.declare_subscriber(
            ctx.keys.alive_all(), lambda s: self._events.put(("z", s.kind, str(s.key_expr))),
            history=True)
        self.on_close(self._lv_zenros.undeclare)
        self._lv_ros = lv.declare_subscriber(
            f"@ros2_lv/{self.domain}/**",
            lambda s: self._events.put(("r", s.kind, str(s.key_expr))), history=True)
        self.on_close(self._lv_ros.undeclare)
        self.logger.info("bridging zenros and rmw_zenoh on ROS domain %d", self.domain)

    # ------------------------------------------------------------ graph events

    def wanted(self, name: str) -> bool:
        return self.name_filter(name)

    def _run(self) -> None:
        while True:
            ev = self._events.get()
            if ev is None:
                return
            side, kind, key = ev
            try:
                with self._graph_lock:
                    if side == "z":
                        self._on_zenros_token(kind, key)
                    else:
                        self._on_ros_token(kind, key)
            except (ZenrosError, ValueError, zenoh.ZError) as exc:
                self.problems(f"token {key}", "cannot bridge %s: %s", key, exc)
            except Exception:  # the graph thread outlives one bad event
                self.logger.exception("graph event %s of %s failed", kind, key)

    def _on_zenros_token(self, kind: zenoh.SampleKind, key: str) -> None:
        tok = self.context.keys.parse_token(key)
        if tok is None or tok.zid == self.zid:
            return
        if self.mirror_graph:
            self.mirror.on_zenros(kind, key, tok)
        if tok.kind not in ("pub", "srv", "act"):
            return
        slot = (tok.kind, tok.name)
        if kind == zenoh.SampleKind.DELETE:
            self._zenros[slot].discard(key)
            if not self._zenros[slot]:
                routes: dict[str, dict[str, Any]] = {
                    "pub": self.outbound, "srv": self.services, "act": self.actions}
                route = routes[tok.kind]
                if tok.name in route:
                    route.pop(tok.name).close()
            return
        self._zenros[slot].add(key)
        if not self.wanted(tok.name):
            return
        if tok.kind == "pub" and tok.name not in self.outbound:
            cls = lookup_type(tok.type)
            self.outbound[tok.name] = _Outbound(self, tok.name, cls, tok.qos)
            self.logger.info("zenros %s (%s) -> rmw_zenoh", tok.name, tok.type)
        elif tok.kind == "srv" and self.bridge_services and tok.name not in self.services:
            self.services[tok.name] = _ServiceOut(self, tok.name, tok.type)
            self.logger.info("zenros service %s (%s) -> rmw_zenoh", tok.name, tok.type)
        elif tok.kind == "act" and self.bridge_actions and tok.name not in self.actions:
            self.actions[tok.name] = ActionOut(self, tok.name, lookup_action(tok.type))
            self.logger.info("zenros action %s (%s) -> rmw_zenoh", tok.name, tok.type)

    def _on_ros_token(self, kind: zenoh.SampleKind, key: str) -> None:
        try:
            ent = Entity.parse(key)
        except RmwZenohError as exc:
            self.problems(f"token {key}", "ignoring a malformed rmw_zenoh token: %s", exc)
            return
        if ent.zid == self.zid:
            return
        if self.mirror_graph:
            self.mirror.on_ros(kind, key, ent)
        if ent.kind is EntityKind.SERVICE:
            self._on_ros_server(kind, key, ent)
            return
        if ent.kind is not EntityKind.PUBLISHER or "/_action/" in ent.topic:
            return  # an action's feedback and status come with its send_goal service
        slot = (ent.topic, ent.dds_type)
        if kind == zenoh.SampleKind.DELETE:
            self._ros[slot].discard(key)
            if not self._ros[slot] and slot in self.inbound:
                self.inbound.pop(slot).close()
            return
        self._ros[slot].add(key)
        if slot in self.inbound or not self.wanted(ent.topic):
            return
        ros_type = dds_to_ros(ent.dds_type)
        cls = zenros_class_of(ros_type)
        if cls is None:
            self.problems(f"type {ros_type}", "ROS 2 topic %s has type %s, which zenros does not "
                          "know: not bridged", ent.topic, ros_type)
            return
        _, ours = type_part(ros_type)
        if ours != ent.type_hash:
            self.problems(f"hash {ros_type}", "ROS 2 topic %s: type %s has hash %s there, %s in "
                          "zenros (another version of the type): not bridged", ent.topic,
                          ros_type, ent.type_hash, ours)
            return
        self.inbound[slot] = _Inbound(self, ent.topic, cls, ent.qos)
        self.logger.info("rmw_zenoh %s (%s) -> zenros", ent.topic, ros_type)

    def _on_ros_server(self, kind: zenoh.SampleKind, key: str, ent: Entity) -> None:
        """An rmw_zenoh service server, or the send_goal service of an action server (its
        other services and topics come with it), served to zenros clients."""
        name, is_action = ent.topic, ent.topic.endswith(ACTION_SEND_GOAL)
        if "/_action/" in name and not is_action:
            return  # cancel_goal, get_result: part of the action the send_goal token brings
        if is_action:
            name = name.removesuffix(ACTION_SEND_GOAL)
        slot = ("act" if is_action else "srv", name)
        route: dict[str, Any] = self.actions_in if is_action else self.services_in
        if kind == zenoh.SampleKind.DELETE:
            self._ros[slot].discard(key)
            if not self._ros[slot] and name in route:
                route.pop(name).close()
            return
        self._ros[slot].add(key)
        if name in route or not self.wanted(name):
            return
        if not (self.bridge_actions if is_action else self.bridge_services):
            return
        ros_type = dds_to_ros(ent.dds_type)
        if is_action:
            ros_type = ros_type.removesuffix("_SendGoal")
        pkg, _, short = ros_type.split("/")
        try:
            typ: Any = (lookup_action if is_action else lookup_service)(f"{pkg}/{short}")
        except UnknownTypeError:
            self.problems(f"type {ros_type}", "ROS 2 %s %s has type %s, which zenros does not "
                          "know: not bridged", "action" if is_action else "service", name,
                          ros_type)
            return
        _, ours = type_part(f"{ros_type}_SendGoal" if is_action else ros_type)
        if ours != ent.type_hash:
            self.problems(f"hash {ros_type}", "ROS 2 %s: type %s has hash %s there, %s in "
                          "zenros (another version of the type): not bridged", name, ros_type,
                          ent.type_hash, ours)
            return
        route[name] = ActionIn(self, name, typ) if is_action else ServiceIn(self, name, typ)
        self.logger.info("rmw_zenoh %s %s (%s) -> zenros", "action" if is_action else "service",
                         name, ros_type)

    def entity(self, kind: EntityKind, name: str, ros_type: str, qos: Qos) -> Entity:
        dds, h = type_part(ros_type)
        return Entity(self.domain, self.zid, 0, next(self._eids), kind, self.namespace, self.name,
                      topic=name, dds_type=dds, type_hash=h, qos=qos)

    def _stop_worker(self) -> None:
        self._events.put(None)
        self._worker.join(5)
        with self._graph_lock:
            routes: list[dict[Any, Any]] = [self.outbound, self.inbound, self.services,
                                            self.services_in, self.actions, self.actions_in]
            for route in routes:
                for b in route.values():
                    b.close()
                route.clear()
            self.mirror.close()


class _Outbound:
    """A zenros topic published on its rmw_zenoh key, with the zenros publisher's reliability,
    durability and depth; a latched topic is transient local on both sides (an advanced
    subscriber with history here, an advanced publisher with a cache there)."""

    def __init__(self, bridge: RmwZenohBridge, topic: str, cls: type[Message], tag: str) -> None:
        self.bridge = bridge
        self.native = codec_for(cls)
        self.cdr = cdr_codec(cls)
        ros_type = ros_name_of(cls)
        s = bridge.session
        zq = QoSProfile.from_tag(tag)
        self.latched = zq.latched
        qos = Qos(depth=zq.depth,
                  reliability=(Reliability.BEST_EFFORT if zq.reliability is ZReliability.BEST_EFFORT
                               else Reliability.RELIABLE),
                  durability=Durability.TRANSIENT_LOCAL if zq.latched else Durability.VOLATILE)
        ent = bridge.entity(EntityKind.PUBLISHER, topic, ros_type, qos)
        self.gid = ent.gid
        self.pub = RmwPublisher(s, data_key(bridge.domain, topic, ros_type), qos, ent.gid)
        self.token = s.liveliness().declare_token(ent.token())
        ctx = bridge.context
        self.sub_token = s.liveliness().declare_token(ctx.keys.entity_token(
            "sub", bridge.fqn, topic, self.native.type_name, zq.tag, ctx.zid, ctx.next_eid()))
        self.topic = topic
        key = ctx.keys.topic(topic)
        if zq.latched:
            self.sub: Any = zext.declare_advanced_subscriber(
                s, key, self._on_sample, allowed_origin=zenoh.Locality.REMOTE,
                history=zext.HistoryConfig(detect_late_publishers=True, max_samples=zq.depth),
                recovery=zext.RecoveryConfig(heartbeat=True, periodic_queries=None),
                subscriber_detection=True)
        else:
            self.sub = s.declare_subscriber(key, self._on_sample,
                                            allowed_origin=zenoh.Locality.REMOTE)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        try:
            data = self.cdr.encode(self.native.decode(sample.payload.to_bytes()))
        except CodecError as exc:
            info = sample.source_info
            sender = str(info.source_id) if info is not None else "unknown"
            self.bridge.problems(f"bad {self.topic} {sender}", "dropping a sample on %s that "
                                 "does not convert: %s", self.topic, exc)
            return
        self.pub.put(data)

    def close(self) -> None:
        self.sub.undeclare()
        self.sub_token.undeclare()  # type: ignore[no-untyped-call]
        self.token.undeclare()  # type: ignore[no-untyped-call]
        self.pub.close()


class _Inbound:
    """An rmw_zenoh topic republished in zenros under its ROS name; a transient-local ROS 2
    publisher is read with history (its cache) and republished latched."""

    def __init__(self, bridge: RmwZenohBridge, topic: str, cls: type[Message], qos: Qos) -> None:
        self.bridge = bridge
        self.topic = topic
        self.cdr = cdr_codec(cls)
        ros_type = ros_name_of(cls)
        qos = qos.normalized()
        zqos = QoSProfile(
            depth=max(1, min(qos.depth, 1000)),
            reliability=(ZReliability.BEST_EFFORT if qos.reliability is Reliability.BEST_EFFORT
                         else ZReliability.RELIABLE),
            durability=(ZDurability.TRANSIENT_LOCAL if qos.durability is Durability.TRANSIENT_LOCAL
                        else ZDurability.VOLATILE))
        self.pub = bridge.create_publisher(cls, topic, zqos)
        s = bridge.session
        ent = bridge.entity(EntityKind.SUBSCRIPTION, topic, ros_type, qos)
        self.token = s.liveliness().declare_token(ent.token())
        self.sub = declare_rmw_subscriber(s, data_key(bridge.domain, topic, ros_type), qos,
                                          self._on_sample)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        try:
            msg = self.cdr.decode(sample.payload.to_bytes())
        except CodecError as exc:
            sender = "unknown"
            if sample.attachment is not None:
                try:
                    sender = Attachment.decode(sample.attachment.to_bytes()).gid.hex()
                except RmwZenohError:
                    pass
            self.bridge.problems(f"bad {self.topic} {sender}", "dropping a sample on %s from %s: "
                                 "%s", self.topic, sender, exc)
            return
        self.pub.publish(msg)

    def close(self) -> None:
        self.sub.undeclare()
        self.token.undeclare()  # type: ignore[no-untyped-call]
        self.bridge.destroy(self.pub)


class _ServiceOut:
    """A zenros service answering rmw_zenoh clients on its service key."""

    def __init__(self, bridge: RmwZenohBridge, name: str, type_name: str) -> None:
        self.bridge = bridge
        self.name = name
        srv = lookup_service(type_name)
        pkg, _, short = srv.name.partition("/")
        ros_type = f"{pkg}/srv/{short}"
        self.req = cdr_codec(srv.Request)
        self.resp = cdr_codec(srv.Response)
        self.client = bridge.create_client(srv, name)
        s = bridge.session
        ent = bridge.entity(EntityKind.SERVICE, name, ros_type, Qos(depth=10))
        # the queryable before the token: a client that sees the service listed has had its
        # route declared first (one session's declarations reach a peer in order)
        self.queryable = s.declare_queryable(data_key(bridge.domain, name, ros_type),
                                             self._on_query, complete=True)
        self.token = s.liveliness().declare_token(ent.token())

    def _on_query(self, query: zenoh.Query) -> None:
        try:
            att, payload = request_attachment(query)
            request = self.req.decode(payload)
        except (CodecError, RmwZenohError) as exc:
            self.bridge.problems(f"bad request {self.name}", "refusing a request to %s: %s",
                                 self.name, exc)
            reply_error(query, str(exc))
            return
        self.bridge.pool.submit(self._answer, query, att, request)

    def _answer(self, query: zenoh.Query, att: Attachment, request: Any) -> None:
        try:
            response = self.client.call(request, timeout=self.bridge.call_timeout)
            data = self.resp.encode(response)
        except (ZenrosError, TimeoutError) as exc:
            reply_error(query, f"{self.name}: {exc}")
            return
        reply_echo(query, data, att)

    def close(self) -> None:
        self.queryable.undeclare()  # type: ignore[no-untyped-call]
        self.token.undeclare()  # type: ignore[no-untyped-call]
        self.bridge.destroy(self.client)
