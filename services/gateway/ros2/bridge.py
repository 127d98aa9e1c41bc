"""`Ros2DdsBridge`: ROS 2 topics on a DDS domain in the zenros graph and zenros topics in
ROS 2, found by DDS discovery (DCPSPublication/DCPSSubscription) and zenros liveliness.

- ROS 2 -> zenros: for each DDS writer on ``rt/<name>`` of another participant whose type
  zenros knows (``pkg::msg::dds_::Name_``, same RIHS01 hash when the writer says it), a DDS
  reader with the writer's QoS and a zenros publisher on ``/<name>``; gone with the last writer.
- zenros -> ROS 2: for each zenros publisher of another session whose type has a ROS 2
  definition, a zenros subscriber (remote samples only) and a DDS writer on ``rt/<name>``.
- never loops: this participant's own writers and readers are not discovered as others',
  its readers ignore its own writers (IGNORE_LOCAL), zenros tokens and samples of the bridge's
  own session are skipped.
- ROS 2 nodes (``ros_discovery_info``) get a node token each in the zenros graph.
- ROS 2 services and action servers are offered to zenros clients (`ServiceRoute`,
  `ActionRoute`); a zenros action server's feedback and status are written to DDS
  (`ActionTopicsOut`; its services cannot be: docs/ros2.md, "Limits").

Bad input: a sample that does not decode is dropped, counted and logged once per sender; an
unknown type or another hash is logged once per topic and the topic is skipped.
"""

from __future__ import annotations

import importlib
import queue
import re
import threading
import uuid
from collections import defaultdict
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import zenoh
from cyclonedds.builtin import (
    BuiltinDataReader,
    BuiltinTopicDcpsPublication,
    BuiltinTopicDcpsSubscription,
)
from cyclonedds.core import InstanceState
from zenros.errors import ConfigError, UnknownTypeError
from zenros.log import LogOnce
from zenros.message import ActionType
from zenros.node import Node
from zenros.qos import QoSProfile
from zenros.registry import lookup_action, lookup_service, lookup_type
from zenros.ros2.domain import NameFilter
from zenros.ros2.registry import definition, ros_name_of, zenros_class_of
from zenros.ros2.typehash import type_hash
from zenros.ros2.typenames import dds_to_ros, ros_to_zenros

from .actions import ActionRoute, ActionTopicsOut
from .graph import RosNodes
from .params import DdsBridgeParameters
from .participant import open_participant
from .qos import zenros_qos
from .routes import Inbound, Outbound
from .services import ServiceRoute

__all__ = ["Ros2DdsBridge"]

_ACTION = "/_action/"
_SEND_GOAL = "/_action/send_goal"


@dataclass
class _Writer:
    """A DDS writer of another participant, as discovery described it."""

    key: uuid.UUID
    participant: uuid.UUID
    name: str
    dds_type: str
    qos: Any
    type_hash: str = ""
    slot: tuple[str, str] = field(default=("", ""))


def _user_hash(qos: Any) -> str:
    from cyclonedds.core import Policy
    ud = qos[Policy.Userdata]
    if ud is None:
        return ""
    m = re.search(rb"typehash=(RIHS01_[0-9a-f]{64})", ud.data)
    return m[1].decode() if m else ""


class Ros2DdsBridge(Node):
    """Parameters: `DdsBridgeParameters` (``domain_id``, ``allow`` and ``deny`` regular
    expressions on ROS names, deny winning, ``depth``: the keep-last depth of topics from
    DDS, whose discovery does not say it, the service and result timeouts, the ``types``
    modules to import)."""

    node_name = "ros2_dds_bridge"

    def setup(self) -> None:
        p = self.declare_parameters(DdsBridgeParameters, read_only=True)
        self.domain = p.domain_id
        self.name_filter = NameFilter(p)
        self.depth = p.depth
        self.service_timeout = p.service_timeout
        self.result_timeout = p.result_timeout
        self._import_types(p.types)
        ctx = self.context
        self.zid = str(ctx.zid)
        self.problems = LogOnce(self.logger)
        self.bad_samples: dict[str, int] = defaultdict(int)
        self.dds_topics: dict[tuple[str, str], Any] = {}
        self.inbound: dict[str, Inbound] = {}
        self.outbound: dict[str, Outbound] = {}
        self.services: dict[str, ServiceRoute] = {}
        self.actions: dict[str, ActionRoute] = {}
        self.actions_out: dict[str, ActionTopicsOut] = {}
        self._zenros_acts: dict[str, set[str]] = defaultdict(set)
        self.pool = ThreadPoolExecutor(8, thread_name_prefix="ros2-dds-calls")
        self.on_close(lambda: self.pool.shutdown(wait=False, cancel_futures=True))
        self._servers: dict[uuid.UUID, str] = {}  # request reader of a ROS 2 server -> name
        self._writers: dict[uuid.UUID, _Writer] = {}
        self._handles: dict[int, _Writer] = {}
        self._zenros_pubs: dict[str, set[str]] = defaultdict(set)
        self._events: queue.Queue[tuple[zenoh.SampleKind, str] | None] = queue.Queue()
        self._graph_lock = threading.Lock()
        self.domain_entity, self.participant = open_participant(self.domain)
        self.on_close(self._delete_participant)  # its readers and writers go with it
        self.guid = self.participant.guid
        self._pubs = BuiltinDataReader(self.participant, BuiltinTopicDcpsPublication)
        self._subs = BuiltinDataReader(self.participant, BuiltinTopicDcpsSubscription)
        self.nodes = self.own(RosNodes(self))
        self._stop = threading.Event()
        self._worker = threading.Thread(target=self._run, name="ros2-dds-bridge", daemon=True)
        self._worker.start()
        self.on_close(self._stop_worker)
        self._lv = ctx.session.liveliness().declare_subscriber(
            ctx.keys.alive_all(), lambda s: self._events.put((s.kind, str(s.key_expr))),
            history=True)
        self.on_close(self._lv.undeclare)
        self.logger.info("bridging zenros and ROS 2 on DDS domain %d", self.domain)

    def _import_types(self, modules: str) -> None:
        for mod in filter(None, (m.strip() for m in modules.split(","))):
            try:
                importlib.import_module(mod)
            except Exception as exc:  # whatever it raised, the bridge cannot start
                raise ConfigError(f"types: cannot import {mod}: {type(exc).__name__}: "
                                  f"{exc}") from exc

    # ------------------------------------------------------------ helpers for the routes

    def wanted(self, name: str) -> bool:
        return self.name_filter(name)

    def bad_sample(self, topic: str, sender: str, exc: Exception) -> None:
        self.bad_samples[topic] += 1
        self.problems(f"bad {topic} {sender}", "dropping a sample on %s from %s that does not "
                      "convert: %s", topic, sender, exc)

    def writer_name(self, handle: int) -> str:
        w = self._handles.get(handle)
        if w is None:
            return ""
        node = self.nodes.node_of_writer(w.key)
        return f"ROS 2 node {node}" if node else f"DDS writer {w.key}"

    # ------------------------------------------------------------ discovery

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                ev = self._events.get(timeout=0.05)
            except queue.Empty:
                ev = None
            try:
                with self._graph_lock:
                    if ev is not None:
                        self._on_zenros_token(*ev)
                    self._poll_dds()
                    self.nodes.poll()
            except Exception as exc:  # noqa: BLE001 the worker outlives any one bad event
                self.problems(f"discovery {type(exc).__name__} {exc}", "discovery: %s: %s",
                              type(exc).__name__, exc)

    def _poll_dds(self) -> None:
        for s in self._pubs.take(64):
            self._on_dds_writer(s)
        for s in self._subs.take(64):
            self._on_dds_reader(s)  # topic readers: no route (a zenros publisher makes one)

    def _on_dds_writer(self, s: Any) -> None:
        info = s.sample_info
        if info.instance_state != InstanceState.Alive or not info.valid_data:
            w = self._writers.pop(s.key, None)
            if w is not None:
                self._handles.pop(info.instance_handle, None)
                self._writer_left(w)
            return
        if s.participant_key == self.guid or s.key in self._writers:
            return
        if not s.topic_name.startswith("rt/"):
            return  # rq/rr (services), ros_discovery_info: not topics
        w = _Writer(s.key, s.participant_key, "/" + s.topic_name[3:], s.type_name, s.qos,
                    _user_hash(s.qos))
        self._writers[s.key] = w
        self._handles[info.instance_handle] = w
        self._writer_joined(w)

    def _on_dds_reader(self, s: Any) -> None:
        """A ROS 2 service server's request reader (``rq/<name>Request``) makes a service
        route, an action server's send_goal reader (``rq/<name>/_action/send_goalRequest``)
        an action route; when the last one of that name leaves, the route goes."""
        info = s.sample_info
        if info.instance_state != InstanceState.Alive or not info.valid_data:
            name = self._servers.pop(s.key, None)
            if name is not None and name not in self._servers.values():
                self._server_left(name)
            return
        topic = s.topic_name
        if s.participant_key == self.guid or not (
                topic.startswith("rq/") and topic.endswith("Request")):
            return
        name = "/" + topic[3:-len("Request")]
        if _ACTION in name and not name.endswith(_SEND_GOAL):
            return  # cancel_goal and get_result: the action route's
        if not self.wanted(name.removesuffix(_SEND_GOAL)):
            return
        self._servers[s.key] = name
        if name.endswith(_SEND_GOAL):
            self._action_server(name.removesuffix(_SEND_GOAL), s)
        elif name not in self.services:
            self._service_server(name, s)

    def _server_left(self, name: str) -> None:
        if name.endswith(_SEND_GOAL):
            route: ServiceRoute | ActionRoute | None = self.actions.pop(
                name.removesuffix(_SEND_GOAL), None)
        else:
            route = self.services.pop(name, None)
        if route is not None:
            route.close()
            self.logger.info("ROS 2 %s %s: its server left, route closed",
                             "action" if isinstance(route, ActionRoute) else "service",
                             route.name)

    def _service_server(self, name: str, s: Any) -> None:
        try:
            ros_type = dds_to_ros(s.type_name).removesuffix("_Request")
            srv = lookup_service(ros_to_zenros(ros_type))
        except (UnknownTypeError, ValueError):
            self.problems(f"srvtype {s.type_name}", "ROS 2 service %s has type %s, which "
                          "zenros does not know: not bridged", name, s.type_name)
            return
        if not self._same_hash(name, s, ros_name_of(srv.Request)):
            return
        self.services[name] = ServiceRoute(self, name, srv, self.service_timeout)
        self.logger.info("ROS 2 service %s (%s) -> zenros", name, ros_type)

    def _action_server(self, name: str, s: Any) -> None:
        if name in self.actions:
            return
        action: ActionType
        try:
            ros_type = dds_to_ros(s.type_name).removesuffix("_SendGoal_Request")
            action = lookup_action(ros_type)
        except (UnknownTypeError, ValueError):
            self.problems(f"acttype {s.type_name}", "ROS 2 action %s has type %s, which "
                          "zenros does not know: not bridged", name, s.type_name)
            return
        if not self._same_hash(name, s, f"{ros_type}_SendGoal_Request"):
            return
        self.actions[name] = ActionRoute(self, name, action)
        self.logger.info("ROS 2 action %s (%s) -> zenros", name, ros_type)

    def _same_hash(self, name: str, s: Any, ros_type: str) -> bool:
        """Whether a DDS request reader's type hash (if it says one) is zenros's."""
        hash_there, ours = _user_hash(s.qos), type_hash(ros_type)
        if hash_there and hash_there != ours:
            self.problems(f"srvhash {name}", "ROS 2 service or action %s: request type %s has "
                          "hash %s there, %s in zenros: not bridged", name, s.type_name,
                          hash_there, ours)
            return False
        return True

    def _writer_joined(self, w: _Writer) -> None:
        if not self.wanted(w.name) or _ACTION in w.name:  # feedback, status: the action's
            return
        try:
            ros_type = dds_to_ros(w.dds_type)
        except UnknownTypeError:
            self.problems(f"type {w.dds_type}", "DDS topic %s has type %s, not a ROS 2 type: "
                          "not bridged", w.name, w.dds_type)
            return
        cls = zenros_class_of(ros_type)
        if cls is None:
            self.problems(f"type {ros_type}", "ROS 2 topic %s has type %s, which zenros does "
                          "not know: not bridged", w.name, ros_type)
            return
        ours = type_hash(ros_type)
        if w.type_hash and w.type_hash != ours:
            self.problems(f"hash {w.name} {ros_type}", "ROS 2 topic %s: type %s has hash %s "
                          "there, %s in zenros (another version of the type): not bridged",
                          w.name, ros_type, w.type_hash, ours)
            return
        w.slot = (w.name, ros_type)
        route = self.inbound.get(w.name)
        if route is not None:
            if ros_name_of(route.cdr.type) != ros_type:
                self.problems(f"conflict {w.name}", "ROS 2 topic %s is published as %s and %s: "
                              "only the first is bridged", w.name,
                              ros_name_of(route.cdr.type), ros_type)
            return
        qos = zenros_qos(w.qos, self.depth)
        self.inbound[w.name] = Inbound(self, w.name, cls, qos)
        self.logger.info("ROS 2 %s (%s) -> zenros", w.name, ros_type)

    def _writer_left(self, w: _Writer) -> None:
        if not w.slot[0]:
            return
        if any(o.slot == w.slot for o in self._writers.values()):
            return
        route = self.inbound.pop(w.name, None)
        if route is not None:
            route.close()
            self.logger.info("ROS 2 %s: no writer left, route closed", w.name)

    def _on_zenros_token(self, kind: zenoh.SampleKind, key: str) -> None:
        tok = self.context.keys.parse_token(key)
        if tok is None or tok.zid == self.zid or tok.kind not in ("pub", "act"):
            return
        name = tok.name
        keys, routes = ((self._zenros_pubs, self.outbound) if tok.kind == "pub"
                        else (self._zenros_acts, self.actions_out))
        if kind == zenoh.SampleKind.DELETE:
            keys[name].discard(key)
            if not keys[name] and name in routes:
                routes.pop(name).close()
                self.logger.info("zenros %s: no %s left, route closed", name,
                                 "publisher" if tok.kind == "pub" else "action server")
            return
        keys[name].add(key)
        if name in routes or not self.wanted(name):
            return
        if tok.kind == "act":
            self._zenros_action(name, tok.type)
            return
        try:
            cls = lookup_type(tok.type)
            definition(ros_name_of(cls))
        except (UnknownTypeError, ValueError) as exc:
            self.problems(f"ztype {name}", "zenros topic %s (%s) has no ROS 2 form: %s",
                          name, tok.type, exc)
            return
        self.outbound[name] = Outbound(self, name, cls, QoSProfile.from_tag(tok.qos))
        self.logger.info("zenros %s (%s) -> ROS 2", name, tok.type)

    def _zenros_action(self, name: str, type_name: str) -> None:
        try:
            route = ActionTopicsOut(self, name, lookup_action(type_name))
        except (UnknownTypeError, ValueError) as exc:
            self.problems(f"zacttype {name}", "zenros action %s (%s) has no ROS 2 form: %s",
                          name, type_name, exc)
            return
        self.actions_out[name] = route
        self.logger.info("zenros action %s (%s): feedback and status -> ROS 2", name,
                         type_name)

    # ------------------------------------------------------------ lifecycle

    def _stop_worker(self) -> None:
        self._stop.set()
        self._worker.join(5)
        with self._graph_lock:
            routes: list[Inbound | Outbound | ServiceRoute | ActionRoute | ActionTopicsOut] = [
                *self.inbound.values(), *self.outbound.values(), *self.services.values(),
                *self.actions.values(), *self.actions_out.values()]
            for r in routes:
                r.close()
            self.inbound.clear()
            self.outbound.clear()
            self.services.clear()
            self.actions.clear()
            self.actions_out.clear()

    def _delete_participant(self) -> None:
        self.participant.__del__()
        if self.domain_entity is not None:
            self.domain_entity.__del__()
