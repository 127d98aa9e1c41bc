"""Actions between zenros and rmw_zenoh, both ways, translated request by request.

rcl_action makes an action three services and two topics under ``<name>/_action/``
(send_goal, cancel_goal, get_result; feedback, status); rmw_zenoh declares each as it declares
any service or topic, so an action server is three ``SS`` and two ``MP`` tokens and a client
three ``SC`` and two ``MS`` tokens. zenros's wire messages (``zenros.action.wire``) have the
ROS layout, so each request is decoded on one side and re-encoded on the other with the goal
ids unchanged: the client's goal id is the goal id on both sides.

- `ActionOut`: a zenros action server answers rmw_zenoh clients. A rejected goal (zenros
  replies ``GoalRejected``) is ``accepted: false``; an unknown goal's result is status 0.
- `ActionIn`: an rmw_zenoh action server answers zenros clients. ``accepted: false`` is
  ``GoalRejected``; a result with status 0 (unknown goal) is ``UnknownGoal``.

Status is transient local with depth 1 on both sides (rcl_action's status QoS); feedback is
reliable, volatile, depth 10.
"""

from __future__ import annotations

import functools
import time
from typing import Any

import zenoh
from zenros.action.transport import (
    parse_error,
    query_once,
    status_publisher,
    status_subscriber,
)
from zenros.action.types import GoalStatusArray
from zenros.action.wire import wire_types
from zenros.codec import Codec
from zenros.errors import CodecError
from zenros.message import ActionType
from zenros.msgs.builtin_interfaces import Time
from zenros.ros2.actions import SERVICES, Topics, action_parts, ros_action_name
from zenros.ros2.cdr import CdrCodec
from zenros.ros2.rmw_zenoh import (
    Durability,
    EntityKind,
    Qos,
    RmwZenohError,
    action_endpoints,
    data_key,
)
from zenros.rpc import error_payload

from .host import BridgeHost
from .rmw_io import (
    Requester,
    RmwPublisher,
    declare_rmw_subscriber,
    reply_echo,
    reply_error,
    request_attachment,
)

__all__ = ["STATUS_QOS", "ActionIn", "ActionOut"]

STATUS_QOS = Qos(depth=1, durability=Durability.TRANSIENT_LOCAL)  # rcl_action's status QoS
FEEDBACK_QOS = Qos(depth=10)
SERVICE_QOS = Qos(depth=10)  # rmw_qos_profile_services_default


class _Action:
    """What both directions share: the endpoints, codecs and the bridge's tokens."""

    def __init__(self, bridge: BridgeHost, name: str, action: ActionType, server: bool) -> None:
        self.bridge = bridge
        self.name = name
        self.action = action
        self.ros_type = ros_action_name(action)
        self.ends = action_endpoints(name, self.ros_type)
        self.parts = action_parts(action)
        t = Topics(action)
        self.fb_native, self.fb_cdr, self.fb_enc = t.fb_native, t.fb_cdr, t.fb_enc
        self.st_native, self.st_cdr = t.st_native, t.st_cdr
        srv_kind = EntityKind.SERVICE if server else EntityKind.CLIENT
        top_kind = EntityKind.PUBLISHER if server else EntityKind.SUBSCRIPTION
        self.entities = {p: bridge.entity(srv_kind, self.ends[p][0], self.ends[p][1], SERVICE_QOS)
                         for p in SERVICES}
        self.entities["feedback"] = bridge.entity(top_kind, *self.ends["feedback"], FEEDBACK_QOS)
        self.entities["status"] = bridge.entity(top_kind, *self.ends["status"], STATUS_QOS)
        self.closers: list[Any] = []

    def key(self, part: str) -> str:
        name, ros_type = self.ends[part]
        return data_key(self.bridge.domain, name, ros_type)

    def declare_tokens(self) -> None:
        lv = self.bridge.session.liveliness()
        for ent in self.entities.values():
            self.closers.append(lv.declare_token(ent.token()))

    def close(self) -> None:
        for c in reversed(self.closers):
            if hasattr(c, "undeclare"):
                c.undeclare()
            else:
                c.close()
        self.closers.clear()


class ActionOut(_Action):
    """A zenros action server, served to rmw_zenoh clients."""

    def __init__(self, bridge: BridgeHost, name: str, action: ActionType) -> None:
        super().__init__(bridge, name, action, server=True)
        s = bridge.session
        keys = bridge.context.keys
        self.feedback = RmwPublisher(s, self.key("feedback"), FEEDBACK_QOS,
                                     self.entities["feedback"].gid)
        self.status = RmwPublisher(s, self.key("status"), STATUS_QOS, self.entities["status"].gid)
        self.closers += [self.feedback, self.status]
        for part in SERVICES:
            self.closers.append(s.declare_queryable(
                self.key(part), functools.partial(self._on_query, part), complete=True))
        self.closers.append(s.declare_subscriber(keys.action(name, "feedback"), self._on_feedback,
                                                 allowed_origin=zenoh.Locality.REMOTE))
        self.closers.append(status_subscriber(s, keys.action(name, "status"), self._on_status))
        self.declare_tokens()

    def _on_query(self, part: str, query: zenoh.Query) -> None:
        p = self.parts[part]
        try:
            att, payload = request_attachment(query)
            req = p.req_cdr.decode(payload)
        except (CodecError, RmwZenohError) as exc:
            self.bridge.problems(f"bad request {self.name}", "refusing a request to %s/%s: %s",
                                 self.name, part, exc)
            reply_error(query, str(exc))
            return
        timeout = self.bridge.result_timeout if part == "get_result" else self.bridge.call_timeout

        def done(reply: zenoh.Reply | None) -> None:
            self.bridge.pool.submit(self._answer, part, query, att, reply)

        query_once(self.bridge.session, self.bridge.context.keys.action(self.name, part),
                   p.req_native.encode(req), p.req_enc, timeout, done)

    def _answer(self, part: str, query: zenoh.Query, att: Any, reply: zenoh.Reply | None) -> None:
        p = self.parts[part]
        w = wire_types(self.action)
        try:
            if reply is None:
                return reply_error(query, f"action {self.name}: no zenros server answered")
            if reply.ok is not None:
                res = p.res_native.decode(reply.ok.payload.to_bytes())
            else:
                kind, message = parse_error(reply.err.payload.to_bytes()) if reply.err else ("", "")
                if part == "send_goal" and kind == "GoalRejected":
                    res = w.SendGoalResponse(accepted=False, stamp=_now())
                elif part == "get_result" and kind == "UnknownGoal":
                    res = w.GetResultResponse(status=0)
                else:
                    return reply_error(query, f"action {self.name} {part}: {kind}: {message}")
            reply_echo(query, p.res_cdr.encode(res), att)
        except (CodecError, zenoh.ZError) as exc:
            self.bridge.problems(f"bad answer {self.name}", "action %s %s: %s", self.name, part,
                                 exc)
            try:
                reply_error(query, f"action {self.name} {part}: {exc}")
            except zenoh.ZError:
                pass

    def _on_feedback(self, sample: zenoh.Sample) -> None:
        self._forward(sample, self.fb_native, self.fb_cdr, self.feedback)

    def _on_status(self, sample: zenoh.Sample) -> None:
        self._forward(sample, self.st_native, self.st_cdr, self.status)

    def _forward(self, sample: zenoh.Sample, native: Codec[Any], cdr: CdrCodec[Any],
                 pub: RmwPublisher) -> None:
        try:
            data = cdr.encode(native.decode(sample.payload.to_bytes()))
        except CodecError as exc:
            self.bridge.problems(f"bad {sample.key_expr}", "dropping a sample on %s: %s",
                                 sample.key_expr, exc)
            return
        pub.put(data)


class ActionIn(_Action):
    """An rmw_zenoh action server, served to zenros clients."""

    def __init__(self, bridge: BridgeHost, name: str, action: ActionType) -> None:
        super().__init__(bridge, name, action, server=False)
        s = bridge.session
        ctx = bridge.context
        keys = ctx.keys
        self.requesters = {p: Requester(s, self.key(p), self.entities[p].gid) for p in SERVICES}
        self.fb_pub = s.declare_publisher(keys.action(name, "feedback"), encoding=self.fb_enc,
                                          congestion_control=zenoh.CongestionControl.BLOCK)
        self.st_pub = status_publisher(s, keys.action(name, "status"), GoalStatusArray)
        self.closers += [self.fb_pub, self.st_pub]
        self._keys = {keys.action(name, p): p for p in SERVICES}
        self.closers.append(s.declare_queryable(keys.action(name, "*"), self._on_query,
                                                complete=True))
        self.closers.append(declare_rmw_subscriber(s, self.key("feedback"), FEEDBACK_QOS,
                                                   self._on_feedback))
        self.closers.append(declare_rmw_subscriber(s, self.key("status"), STATUS_QOS,
                                                   self._on_status))
        self.declare_tokens()
        self.closers.append(s.liveliness().declare_token(keys.entity_token(
            "act", bridge.fqn, name, action.name, "", ctx.zid, ctx.next_eid())))

    def _on_query(self, query: zenoh.Query) -> None:
        part = self._keys.get(str(query.key_expr))
        if part is None:
            return reply_error(query, error_payload(
                "BadRequest", f"action {self.name}: no such request {query.key_expr}").decode())
        p = self.parts[part]
        try:
            payload = query.payload.to_bytes() if query.payload is not None else b""
            req = p.req_native.decode(payload)
            data = p.req_cdr.encode(req)
        except CodecError as exc:
            query.reply_err(error_payload("BadRequest", f"action {self.name} {part}: {exc}"))
            query.drop()  # type: ignore[no-untyped-call]
            return
        timeout = self.bridge.result_timeout if part == "get_result" else self.bridge.call_timeout

        def done(payload: bytes | None, why: str) -> None:
            self.bridge.pool.submit(self._answer, part, query, payload, why)

        self.requesters[part].call(data, timeout, done)

    def _answer(self, part: str, query: zenoh.Query, payload: bytes | None, why: str) -> None:
        p = self.parts[part]
        try:
            if payload is None:
                kind = "ServerUnavailable" if why == "no reply" else "RemoteError"
                query.reply_err(error_payload(kind, f"action {self.name} {part}: {why}"))
                return
            res = p.res_cdr.decode(payload)
            if part == "send_goal" and not res.accepted:
                query.reply_err(error_payload("GoalRejected", "rejected by the ROS 2 server"))
            elif part == "get_result" and res.status == 0:
                query.reply_err(error_payload("UnknownGoal", "the ROS 2 server does not know "
                                              "this goal"))
            else:
                query.reply(query.key_expr, p.res_native.encode(res), encoding=p.res_enc)
        except (CodecError, zenoh.ZError) as exc:
            self.bridge.problems(f"bad answer {self.name}", "action %s %s: %s", self.name, part,
                                 exc)
            try:
                query.reply_err(error_payload("BadResponse", str(exc)))
            except zenoh.ZError:
                pass
        finally:
            query.drop()  # type: ignore[no-untyped-call]

    def _on_feedback(self, sample: zenoh.Sample) -> None:
        msg = self._decode(sample, self.fb_cdr)
        if msg is not None:
            self.fb_pub.put(self.fb_native.encode(msg))

    def _on_status(self, sample: zenoh.Sample) -> None:
        msg = self._decode(sample, self.st_cdr)
        if msg is not None:
            self.st_pub.put(self.st_native.encode(msg))

    def _decode(self, sample: zenoh.Sample, cdr: CdrCodec[Any]) -> Any:
        try:
            return cdr.decode(sample.payload.to_bytes())
        except CodecError as exc:
            self.bridge.problems(f"bad {sample.key_expr}", "dropping a sample on %s: %s",
                                 sample.key_expr, exc)
            return None


def _now() -> Time:
    ns = time.time_ns()
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)
