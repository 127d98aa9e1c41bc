"""`ActionClient`: sends goals to one action, follows their status and feedback, fetches results,
and notices (through liveliness) a server that dies mid-goal."""

from __future__ import annotations

import threading
import uuid
import weakref
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import zenoh

from ..callbacks import make_dispatch
from ..codec import codec_for
from ..errors import (
    ActionError,
    ActionServerUnavailableError,
    CodecError,
    EncodeError,
    GoalRejectedError,
    ZenrosTimeout,
)
from ..log import Throttle
from ..message import ActionType
from ..msgs.builtin_interfaces import Time
from ..names import Token
from .client_goal import ClientGoalHandle, GoalResult
from .transport import encoding_for, parse_error, status_subscriber
from .types import (
    ZERO_UUID,
    CancelGoalRequest,
    CancelGoalResponse,
    GoalInfo,
    GoalStatus,
    GoalStatusArray,
    uuid_from_msg,
    uuid_msg,
)
from .wire import wire_types

if TYPE_CHECKING:
    from ..node import Node

__all__ = ["ActionClient"]

_BEST = zenoh.QueryTarget.BEST_MATCHING


class ActionClient:
    """A client of action ``name`` with ``action_type``.

    Args:
        node: the node that owns the client (closing the node closes it).
        action_type: e.g. ``example_interfaces.Fibonacci``.
        name: the action name, resolved like a topic name.
        send_timeout: seconds to wait for a server's answer to a goal.
        result_timeout: seconds one result request waits before it is renewed (a goal may run
            longer; the request is simply sent again).
    """

    def __init__(self, node: Node, action_type: ActionType, name: str, *,
                 send_timeout: float = 10.0, result_timeout: float = 60.0) -> None:
        self.action_type = action_type
        self.name = node.resolve_name(name, "action")
        self.send_timeout = send_timeout
        self.result_timeout = result_timeout
        self.logger = node.logger
        self._ctx = ctx = node.context
        self._wire = wire = wire_types(action_type)
        self._sg_req = codec_for(wire.SendGoalRequest)
        self._sg_res = codec_for(wire.SendGoalResponse)
        self._gr_req = codec_for(wire.GetResultRequest)
        self._gr_res = codec_for(wire.GetResultResponse)
        self._fb = codec_for(wire.FeedbackMessage)
        self._status = codec_for(GoalStatusArray)
        self._cg_req = codec_for(CancelGoalRequest)
        self._cg_res = codec_for(CancelGoalResponse)
        self._enc = {t: encoding_for(t) for t in (wire.SendGoalRequest, wire.GetResultRequest,
                                                  CancelGoalRequest)}
        self._keys = {p: ctx.keys.action(self.name, p)
                      for p in ("send_goal", "cancel_goal", "get_result", "feedback", "status")}
        self._lock = threading.Lock()
        self._handles: dict[bytes, ClientGoalHandle] = {}
        self._throttle = Throttle(5.0)
        self._status_lock = threading.Lock()
        self._status_raw: bytes | None = None
        self.closed = False
        s = ctx.session
        self._fb_sub: Any = s.declare_subscriber(self._keys["feedback"], self._on_feedback)
        self._status_sub: Any = status_subscriber(s, self._keys["status"], self._on_status)
        self._graph = ctx.graph
        ref = weakref.ref(self)
        self._graph.add_listener(lambda ev, tok: _forward(ref, ev, tok))
        node._track(self)

    # ------------------------------------------------------------------ server presence

    def server_is_ready(self) -> bool:
        return bool(self._graph.action_servers(self.name))

    def wait_for_server(self, timeout: float | None = None) -> bool:
        """Block until a server for this action is in the graph; False on timeout."""
        return self._graph.wait_for_action(self.name, timeout)

    # ------------------------------------------------------------------ goals

    def send_goal(self, goal: Any, feedback_callback: Callable[[Any], Any] | None = None,
                  timeout: float | None = None) -> GoalResult:
        """Send ``goal`` and block until it ends; see `ClientGoalHandle.result` for errors."""
        return self.send_goal_async(goal, feedback_callback).result(timeout)

    def send_goal_async(self, goal: Any,
                        feedback_callback: Callable[[Any], Any] | None = None) -> ClientGoalHandle:
        """Send ``goal`` and return its handle at once.

        ``feedback_callback(msg)`` gets each ``<Name>_FeedbackMessage`` (``msg.feedback``,
        ``msg.goal_id``) in order; a plain function runs on Zenoh's thread, an ``async def`` one
        on the node's event loop.

        Raises:
            EncodeError: ``goal`` is not the action's Goal type.
        """
        if type(goal) is not self.action_type.Goal:
            raise EncodeError(f"action {self.name} takes {codec_for(self.action_type.Goal).type_name}"
                              f" goals, got {type(goal).__name__}")
        if self.closed:
            raise ActionError(f"action client {self.name} is closed")
        gid = uuid.uuid4()
        data = self._sg_req.encode(self._wire.SendGoalRequest(goal_id=uuid_msg(gid), goal=goal))
        dispatch = None if feedback_callback is None else make_dispatch(
            feedback_callback, executor=self._ctx.executor, logger=self.logger,
            what=f"feedback of {self.name}", depth=100)
        handle = ClientGoalHandle(self, gid, goal, dispatch)
        with self._lock:
            self._handles[handle._key] = handle
        handle.add_done_callback(self._forget)
        self._get("send_goal", data, self.send_timeout,
                  lambda reply: self._on_send_reply(handle, reply))
        self._request_result(handle)  # pipelined: the server holds it until the goal ends
        return handle

    def _forget(self, handle: ClientGoalHandle) -> None:
        with self._lock:
            self._handles.pop(handle._key, None)

    def _get(self, part: str, payload: bytes, timeout: float,
             done: Callable[[zenoh.Reply | None], None]) -> None:
        """A non-blocking query: ``done(reply)`` runs once, on the first reply, or with None
        when the query ends without one (no server)."""
        lock = threading.Lock()
        called = False

        def once(reply: zenoh.Reply | None) -> None:
            nonlocal called
            with lock:
                if called:
                    return
                called = True
            done(reply)

        # indirect=False: run on Zenoh's own thread; the default starts a thread per query
        handler = zenoh.handlers.Callback(once, lambda: once(None), indirect=False)
        self._ctx.session.get(
            self._keys[part], handler,
            payload=payload, encoding=self._enc[self._req_type(part)], target=_BEST,
            timeout=timeout)

    def _req_type(self, part: str) -> Any:
        return {"send_goal": self._wire.SendGoalRequest, "get_result": self._wire.GetResultRequest,
                "cancel_goal": CancelGoalRequest}[part]

    def _on_send_reply(self, h: ClientGoalHandle, reply: zenoh.Reply | None) -> None:
        if reply is None:
            h._fail(None, ActionServerUnavailableError(
                f"no action server answered goal {h.goal_id} on {self.name}"))
            return
        if reply.ok is None:
            assert reply.err is not None
            kind, message = parse_error(reply.err.payload.to_bytes())
            if kind == "Timeout":
                h._fail(None, ZenrosTimeout(f"action {self.name} did not answer goal {h.goal_id} "
                                            f"within {self.send_timeout:g} s"))
            else:
                h._fail(GoalStatus.REJECTED, GoalRejectedError(
                    f"action {self.name} refused goal {h.goal_id}: {message}"), message)
            return
        try:
            res = self._sg_res.decode(reply.ok.payload.to_bytes())
        except CodecError as exc:
            h._fail(None, ActionError(f"action {self.name}: bad send_goal response: {exc}"))
            return
        rid = reply.replier_id
        if h._set_accepted(res.accepted, res.stamp, res.reason, str(rid.zid) if rid else ""):
            self._request_result(h)

    # ------------------------------------------------------------------ results

    def _request_result(self, h: ClientGoalHandle) -> None:
        if h.done or self.closed:
            return
        data = self._gr_req.encode(self._wire.GetResultRequest(goal_id=uuid_msg(h.goal_id)))
        early = h.accepted is None
        self._get("get_result", data, self.result_timeout,
                  lambda reply: self._on_result_reply(h, reply, early))

    def _on_result_reply(self, h: ClientGoalHandle, reply: zenoh.Reply | None,
                         early: bool) -> None:
        if h.done:
            return
        if reply is not None and reply.ok is not None:
            try:
                res = self._gr_res.decode(reply.ok.payload.to_bytes())
            except CodecError as exc:
                h._fail(None, ActionError(f"action {self.name}: bad result for goal "
                                          f"{h.goal_id}: {exc}"))
                return
            h._finish(_status(res.status), res.result)
            return
        kind, message = ("", "") if reply is None or reply.err is None else \
            parse_error(reply.err.payload.to_bytes())
        if kind == "GoalRejected":
            h._fail(GoalStatus.REJECTED, GoalRejectedError(
                f"action {self.name} rejected goal {h.goal_id}: {message}"), message)
        elif early and kind in ("UnknownGoal", ""):
            # The pipelined request overtook the goal: ask again once the goal is accepted.
            if not h._defer_result_request():
                self._request_result(h)
        elif kind == "UnknownGoal":
            h._finish(GoalStatus.LOST, self.action_type.Result(), message)
        elif kind == "Timeout":
            self._retry_or_lose(h)
        elif not kind:
            self._retry_or_lose(h, delay=0.1)
        else:
            h._fail(None, ActionError(f"action {self.name}: result of goal {h.goal_id}: "
                                      f"{message}"))

    def _retry_or_lose(self, h: ClientGoalHandle, delay: float = 0.0) -> None:
        """No result yet (query timed out, or no server answered): ask again, unless the
        server that took the goal is gone."""
        if not self._server_alive(h):
            self._lose(h)
        elif delay <= 0:
            self._request_result(h)
        else:
            threading.Timer(delay, self._request_result, (h,)).start()

    def _server_alive(self, h: ClientGoalHandle) -> bool:
        servers = self._graph.action_servers(self.name)
        return any(t.zid == h._server_zid for t in servers) if h._server_zid else bool(servers)

    def _lose(self, h: ClientGoalHandle) -> None:
        h._finish(GoalStatus.LOST, self.action_type.Result(),
                  f"action server {self.name} went away while goal {h.goal_id} was "
                  f"{h.status.name}")

    def _on_graph(self, event: str, tok: Token) -> None:
        if event != "delete" or tok.kind != "act" or tok.name != self.name:
            return
        with self._lock:
            handles = [h for h in self._handles.values() if h.accepted]
        for h in handles:
            if not self._server_alive(h):
                self._lose(h)

    # ------------------------------------------------------------------ topics

    def _on_feedback(self, sample: zenoh.Sample) -> None:
        try:
            msg = self._fb.decode(sample.payload.to_bytes())
        except CodecError as exc:
            self._bad_sample("feedback", exc)
            return
        h = self._handles.get(bytes(msg.goal_id.uuid))
        if h is not None and h._on_feedback is not None and not h.done:
            h._on_feedback(msg)

    def _on_status(self, sample: zenoh.Sample) -> None:
        # Decoded when a handle's status is read (`refresh_status`), not here: results and
        # acceptance come by query, so this keeps status arrays off the goal's critical path.
        self._status_raw = sample.payload.to_bytes()

    def refresh_status(self) -> None:
        """Apply the latest status array to this client's goal handles."""
        with self._status_lock:
            raw, self._status_raw = self._status_raw, None
            if raw is None:
                return
            try:
                arr = self._status.decode(raw)
            except CodecError as exc:
                self._bad_sample("status", exc)
                return
            for st in arr.status_list:
                h = self._handles.get(bytes(st.goal_info.goal_id.uuid))
                if h is not None:
                    h._advance(GoalStatus(st.status))

    def _bad_sample(self, part: str, exc: Exception) -> None:
        if self._throttle.allow(part):
            self.logger.error("action %s: cannot decode %s: %s", self.name, part, exc)

    # ------------------------------------------------------------------ cancel

    def cancel_all_goals(self, timeout: float = 5.0) -> list[uuid.UUID]:
        """Cancel every goal of the server (any client's); return the goals now canceling."""
        return self._cancel(ZERO_UUID, Time(), timeout)

    def cancel_goals_before(self, stamp: Time, timeout: float = 5.0) -> list[uuid.UUID]:
        """Cancel every goal the server accepted at or before ``stamp``."""
        return self._cancel(ZERO_UUID, stamp, timeout)

    def _cancel(self, goal_id: uuid.UUID, stamp: Time, timeout: float) -> list[uuid.UUID]:
        req = CancelGoalRequest(goal_info=GoalInfo(goal_id=uuid_msg(goal_id), stamp=stamp))
        done = threading.Event()
        replies: list[zenoh.Reply | None] = []

        def on_reply(reply: zenoh.Reply | None) -> None:
            replies.append(reply)
            done.set()

        self._get("cancel_goal", self._cg_req.encode(req), timeout, on_reply)
        done.wait(timeout + 1.0)
        reply = replies[0] if replies else None
        if reply is None:
            raise ActionServerUnavailableError(f"no action server answered cancel on {self.name}")
        if reply.ok is None:
            assert reply.err is not None
            kind, message = parse_error(reply.err.payload.to_bytes())
            if kind == "Timeout":
                raise ZenrosTimeout(f"action {self.name} did not answer cancel in {timeout:g} s")
            raise ActionError(f"action {self.name}: cancel failed: {message}")
        res = self._cg_res.decode(reply.ok.payload.to_bytes())
        return [uuid_from_msg(g.goal_id) for g in res.goals_canceling]

    # ------------------------------------------------------------------ lifecycle

    def close(self) -> None:
        """Undeclare the subscriptions; goals still waiting for an end fail with ActionError."""
        if self.closed:
            return
        self.closed = True
        self._fb_sub.undeclare()
        self._status_sub.undeclare()
        with self._lock:
            handles = list(self._handles.values())
        for h in handles:
            h._fail(None, ActionError(f"action client {self.name} closed before goal "
                                      f"{h.goal_id} ended"))

    def __repr__(self) -> str:
        return f"<ActionClient {self.name} [{self.action_type.name}]>"


def _status(value: int) -> GoalStatus:
    try:
        return GoalStatus(value)
    except ValueError:
        return GoalStatus.UNKNOWN


def _forward(ref: weakref.ReferenceType[ActionClient], event: str, tok: Token) -> None:
    client = ref()
    if client is not None and not client.closed:
        client._on_graph(event, tok)

