"""A ROS 2 action server (rclpy, on DDS elsewhere) offered to zenros action clients.

rcl_action makes an action three services and two topics under ``<name>/_action/``: the
server reads ``rq/<name>/_action/{send_goal,cancel_goal,get_result}Request`` and writes the
replies on ``rr/...Reply``, and writes ``rt/<name>/_action/feedback`` (reliable, volatile,
depth 10) and ``rt/<name>/_action/status`` (reliable, transient local, depth 1). The server's
send_goal request reader makes the route: a `Requester` per service, DDS readers of feedback and
status republished on the zenros action's keys, a queryable answering the zenros client's
requests (``<prefix>/action/<name>/{send_goal,cancel_goal,get_result}``) and an action-server
token, so `ActionClient.wait_for_server` finds it.

zenros's wire messages have ROS 2's layout, so each request is decoded from zenros's encoding
and written as CDR with the goal id unchanged. ``accepted: false`` is answered as zenros's
``GoalRejected``, a result with status 0 (unknown goal) as ``UnknownGoal``, a server that does
not answer in time as ``Timeout`` (the client asks for a result again). Each service keeps one
request in flight (`Requester`): results of several goals are asked for one after the other.
"""

from __future__ import annotations

import functools
from typing import Any

import zenoh
from cyclonedds._clayer import ddspy_write
from cyclonedds.core import Listener
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from zenros.action.transport import answer, answer_err, status_publisher, status_subscriber
from zenros.action.types import GoalStatusArray
from zenros.codec import Codec
from zenros.errors import CodecError, ZenrosTimeout
from zenros.message import ActionType
from zenros.qos import QOS_DEFAULT, QOS_LATCHED
from zenros.ros2.actions import SERVICES, Topics, action_parts, ros_action_name
from zenros.ros2.cdr import CdrCodec
from zenros.ros2.typehash import type_hash

from .host import BridgeHost
from .qos import dds_qos
from .routes import dds_topic, take_valid
from .services import Requester

__all__ = ["ActionRoute", "ActionTopicsOut"]


class ActionRoute:
    """zenros action clients -> a ROS 2 action server on DDS."""

    def __init__(self, bridge: BridgeHost, name: str, action: ActionType) -> None:
        self.bridge = bridge
        self.name = name
        self.action = action
        self.calls = 0
        self.parts = action_parts(action)
        self.topics = Topics(action)
        ros = ros_action_name(action)
        self.requesters = {
            p: Requester(bridge, f"{name}/_action/{p}", part.req_cdr.ros_name,
                         part.res_cdr.ros_name)
            for p, part in self.parts.items()}
        ctx = bridge.context
        s = ctx.session
        keys = ctx.keys
        self.fb_pub = s.declare_publisher(keys.action(name, "feedback"),
                                          encoding=self.topics.fb_enc,
                                          congestion_control=zenoh.CongestionControl.BLOCK)
        self.st_pub = status_publisher(s, keys.action(name, "status"), GoalStatusArray)
        self.readers = [
            self._reader("feedback", f"{ros}_FeedbackMessage", QOS_DEFAULT,
                         self.topics.fb_cdr, self.fb_pub),
            self._reader("status", "action_msgs/msg/GoalStatusArray", QOS_LATCHED,
                         self.topics.st_cdr, self.st_pub),
        ]
        self._keys = {keys.action(name, p): p for p in SERVICES}
        self.queryable = s.declare_queryable(keys.action(name, "*"), self._on_query,
                                             complete=True)
        self.token = s.liveliness().declare_token(keys.entity_token(
            "act", bridge.fqn, name, action.name, "", ctx.zid, ctx.next_eid()))

    def _reader(self, part: str, ros_type: str, qos: Any, cdr: CdrCodec[Any],
                pub: Any) -> DataReader[Any]:
        topic = dds_topic(self.bridge, f"{self.name}/_action/{part}", ros_type)
        on_data = functools.partial(self._forward, part, cdr, pub)
        reader: DataReader[Any] = DataReader(
            self.bridge.participant, topic, qos=dds_qos(qos, type_hash(ros_type), writer=False),
            listener=Listener(on_data_available=on_data))  # type: ignore[no-untyped-call]
        on_data(reader)  # the latched status may be there already
        return reader

    def _forward(self, part: str, cdr: CdrCodec[Any], pub: Any, reader: Any) -> None:
        native = self.topics.fb_native if part == "feedback" else self.topics.st_native
        for data, info in take_valid(reader):
            try:
                msg = cdr.decode(data)
            except CodecError as exc:
                self.bridge.bad_sample(f"{self.name}/_action/{part}",
                                       self.bridge.writer_name(info.publication_handle)
                                       or str(info.publication_handle), exc)
                continue
            pub.put(native.encode(msg))

    def _on_query(self, query: zenoh.Query) -> None:
        part = self._keys.get(str(query.key_expr))
        if part is None:
            answer_err(query, "BadRequest", f"action {self.name}: no such request "
                       f"{query.key_expr}")
            return
        p = self.parts[part]
        try:
            payload = query.payload.to_bytes() if query.payload is not None else b""
            data = p.req_cdr.encode(p.req_native.decode(payload))
        except CodecError as exc:
            answer_err(query, "BadRequest", f"action {self.name} {part}: {exc}")
            return
        self.bridge.pool.submit(self._call, part, query, data)  # DDS calls block

    def _call(self, part: str, query: zenoh.Query, data: bytes) -> None:
        p = self.parts[part]
        timeout = (self.bridge.result_timeout if part == "get_result"
                   else self.bridge.service_timeout)
        try:
            try:
                res = self.requesters[part].call(data, timeout, p.res_cdr.decode)
            except ZenrosTimeout as exc:
                answer_err(query, "Timeout", str(exc))
                return
            self.calls += 1
            if part == "send_goal" and not res.accepted:
                answer_err(query, "GoalRejected", "rejected by the ROS 2 server")
            elif part == "get_result" and res.status == 0:
                answer_err(query, "UnknownGoal", "the ROS 2 server does not know this goal")
            else:
                answer(query, p.res_native.encode(res), p.res_enc)
        except (CodecError, zenoh.ZError) as exc:
            self.bridge.problems(f"bad answer {self.name}", "action %s %s: %s", self.name,
                                 part, exc)
            try:
                answer_err(query, "BadResponse", f"action {self.name} {part}: {exc}")
            except zenoh.ZError:
                pass

    def close(self) -> None:
        self.token.undeclare()  # type: ignore[no-untyped-call]
        self.queryable.undeclare()  # type: ignore[no-untyped-call]
        for r in self.readers:
            r.set_listener(None)
            r.__del__()
        for q in self.requesters.values():
            q.close()
        self.fb_pub.undeclare()  # type: ignore[no-untyped-call]
        self.st_pub.undeclare()


class ActionTopicsOut:
    """A zenros action server's feedback and status written to DDS as rcl_action names them
    (``rt/<name>/_action/feedback``, ``rt/<name>/_action/status``, transient local), so ROS 2
    nodes list the action (``rclpy.action.get_action_names_and_types``) and can follow its
    goals. Its three services are not offered on DDS: a Fast DDS client drops every reply
    cyclonedds can write (no related-sample identity; docs/ros2.md, "Limits"), so an rclpy
    ActionClient's ``wait_for_server`` stays False rather than sending goals that would run
    with their client never told."""

    def __init__(self, bridge: BridgeHost, name: str, action: ActionType) -> None:
        self.bridge = bridge
        self.name = name
        self.action = action
        t = Topics(action)
        ros = ros_action_name(action)
        self.forwarded = 0
        ctx = bridge.context
        s = ctx.session
        fb_writer = self._writer("feedback", f"{ros}_FeedbackMessage", QOS_DEFAULT)
        st_writer = self._writer("status", "action_msgs/msg/GoalStatusArray", QOS_LATCHED)
        self.writers = [fb_writer, st_writer]
        self.fb_sub = s.declare_subscriber(
            ctx.keys.action(name, "feedback"),
            functools.partial(self._forward, "feedback", t.fb_native, t.fb_cdr, fb_writer),
            allowed_origin=zenoh.Locality.REMOTE)
        self.st_sub = status_subscriber(
            s, ctx.keys.action(name, "status"),
            functools.partial(self._forward, "status", t.st_native, t.st_cdr, st_writer))

    def _writer(self, part: str, ros_type: str, qos: Any) -> DataWriter[Any]:
        topic = dds_topic(self.bridge, f"{self.name}/_action/{part}", ros_type)
        return DataWriter(self.bridge.participant, topic,
                          qos=dds_qos(qos, type_hash(ros_type), writer=True))

    def _forward(self, part: str, native: Codec[Any], cdr: CdrCodec[Any], writer: Any,
                 sample: zenoh.Sample) -> None:
        ts = sample.timestamp
        sender = str(ts.get_id()) if ts is not None else "unknown"
        if sender == self.bridge.zid:  # the bridge's own (an rclpy server's, republished)
            return
        try:
            data = cdr.encode(native.decode(sample.payload.to_bytes()))
        except CodecError as exc:
            self.bridge.bad_sample(f"{self.name}/_action/{part}", f"session {sender}", exc)
            return
        try:
            ddspy_write(writer._ref, data + bytes(-len(data) & 3))
        except Exception as exc:  # noqa: BLE001 the writer is being deleted
            self.bridge.problems(f"write {self.name} {part}", "cannot write %s %s to DDS: %s",
                                 self.name, part, exc)
            return
        self.forwarded += 1

    def close(self) -> None:
        self.fb_sub.undeclare()  # type: ignore[no-untyped-call]
        self.st_sub.undeclare()
        for w in self.writers:
            w.__del__()
