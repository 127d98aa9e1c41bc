"""`ActionClient`: sends goals to one action, follows their status and feedback, fetches results,
and notices (through liveliness) a server that dies mid-goal."""

from __future__ import annotations

import threading
import time
import uuid
import weakref
from collections.abc import Callable
from typing import Any, Generic

import zenoh

from ..callbacks import make_dispatch
from ..codec import codec_for, split_encoding
from ..errors import (
    ActionError,
    ActionServerUnavailableError,
    CodecError,
    EncodeError,
    GoalRejectedError,
    ZenrosTimeout,
)
from ..keytag import key_tag, misrouted
from ..log import Throttle
from ..message import ActionType, F, G, R, normalize_type_name
from ..msgs.builtin_interfaces import Time
from ..names import Token
from ..reach import REACH_GRACE, RELINK, Reach
from .cancel import request_cancel
from .client_goal import ClientGoalHandle, GoalResult
from .host import ActionHost
from .inbox import Inbox
from .transport import (
    RESULT_ON_GOAL,
    accepted_stamp,
    encoding_for,
    parse_error,
    query_once,
    query_replies,
    status_subscriber,
)
from .types import (
    ZERO_UUID,
    GoalStatus,
    GoalStatusArray,
    uuid_msg,
)
from .wire import wire_types

__all__ = ["ActionClient"]

LOST_TIMEOUT = 3.0  # seconds a goal's server may be away (its link made again) before LOST
ABSENT_POLL = 0.1  # seconds between looks for a server that went away


class ActionClient(Generic[G, R, F]):
    """A client of action ``name`` with ``action_type`` (goals of type G, results of type R,
    feedback of type F: `Node.create_action_client` infers them from ``action_type``).

    Args:
        node: the node that owns the client (closing the node closes it).
        action_type: e.g. ``example_interfaces.Fibonacci``.
        name: the action name, resolved like a topic name.
        send_timeout: seconds to wait for a server's answer to a goal.
        result_timeout: seconds one result request waits before it is renewed (a goal may run
            longer; the request is simply sent again).
        lost_timeout: seconds the server that took a goal may be gone from the graph before
            the goal is reported LOST. A session whose link dropped (a lease that ran out on
            a starved box, a pulled cable) comes back with its goals still running; a server
            back within this time is asked for the result again.
        reach_grace: seconds a goal or cancel request no server answered is sent again
            while the graph lists a server (`zenros.reach`; the CLI waits its
            ``--server-timeout``).
    """

    def __init__(self, node: ActionHost, action_type: ActionType[G, R, F], name: str, *,
                 send_timeout: float = 10.0, result_timeout: float = 60.0,
                 lost_timeout: float = LOST_TIMEOUT,
                 reach_grace: float = REACH_GRACE) -> None:
        self.action_type = action_type
        self.name = node.resolve_name(name, "action")
        self.send_timeout = send_timeout
        self.result_timeout = result_timeout
        self.lost_timeout = lost_timeout
        self.reach_grace = reach_grace
        self.logger = node.logger
        self._ctx = ctx = node.context
        self._wire = wire = wire_types(action_type)
        self._sg_req, self._sg_res, self._gr_req, self._gr_res, self._fb = wire.codecs()
        self._status = codec_for(GoalStatusArray)
        self._enc = {"send_goal": encoding_for(wire.SendGoalRequest),
                     "get_result": encoding_for(wire.GetResultRequest)}
        self._result_enc = encoding_for(wire.GetResultResponse)
        self._fb_enc = encoding_for(wire.FeedbackMessage)
        self._keys = {p: ctx.keys.action(self.name, p)
                      for p in ("send_goal", "cancel_goal", "get_result", "feedback", "status")}
        self._tags = {p: key_tag(self._keys[p]) for p in ("feedback", "status")}
        self._send_key = zenoh.KeyExpr(self._keys["send_goal"])  # parsed once, not per goal
        self._lock = threading.Lock()
        self._handles: dict[bytes, ClientGoalHandle[G, R]] = {}
        self._absent_since: dict[bytes, float] = {}  # goals whose server was missed: since when
        self._throttle = Throttle(5.0)
        self._status_lock = threading.Lock()
        self._status_raw: bytes | None = None
        self.closed = False
        s = ctx.session
        self._inbox = Inbox(f"action-client{self.name}", self.logger)
        self._fb_sub: Any = s.declare_subscriber(
            self._keys["feedback"], zenoh.handlers.Callback(self._on_feedback, indirect=False))
        self._status_sub: Any = status_subscriber(s, self._keys["status"], self._on_status)
        self._graph = ctx.graph
        on_graph = weakref.WeakMethod(self._on_graph)  # the graph does not keep the client

        def forward(event: str, tok: Token) -> None:
            method = on_graph()
            if method is not None:
                method(event, tok)

        self._unlisten = self._graph.add_listener(forward)
        self._token: Any = s.liveliness().declare_token(ctx.keys.entity_token(
            "actc", node.fqn, self.name, action_type.name, "", ctx.zid, ctx.next_eid()))
        node.add_waitable(self)

    # ------------------------------------------------------------------ server presence

    def server_is_ready(self) -> bool:
        return bool(self._graph.action_servers(self.name))

    def wait_for_server(self, timeout: float | None = None) -> bool:
        """Block until a server for this action is in the graph; False on timeout."""
        return self._graph.wait_for_action(self.name, timeout)

    # ------------------------------------------------------------------ goals

    def send_goal(self, goal: G, feedback_callback: Callable[[Any], Any] | None = None,
                  timeout: float | None = None) -> GoalResult[R]:
        """Send ``goal`` and block until it ends; see `ClientGoalHandle.result` for errors.

        The calling thread reads the goal's replies itself (acceptance, then result) from a
        Zenoh channel, as a service call does: no Python runs on Zenoh's threads for them.
        A goal that is accepted and ends within the query (``send_timeout``), with no feedback
        callback, needs no handle: nobody else can see it, and its result is returned as it
        comes. Anything else (feedback, a rejection, an error, a longer goal) goes through a
        registered `ClientGoalHandle`.
        """
        start = time.monotonic()
        gid, data = self._encode_goal(goal)
        wait = self.send_timeout if timeout is None else min(self.send_timeout, timeout)
        h = None if feedback_callback is None else self._register(gid, goal, feedback_callback)
        reach = Reach(self.server_is_ready, wait, self.reach_grace, RELINK)
        while True:  # again while no server answered but the graph lists one
            replies = self._ctx.session.get(
                self._send_key, payload=data, encoding=self._enc["send_goal"],
                target=zenoh.QueryTarget.BEST_MATCHING, consolidation=zenoh.ConsolidationMode.NONE,
                timeout=reach.attempt(), attachment=RESULT_ON_GOAL,
                allowed_destination=self._ctx.destination(self._keys["send_goal"]))
            first: zenoh.Reply | None = None  # the acceptance (or the refusal)
            lost = False  # the query timed out with no answer: it is sent again
            for reply in replies:
                if first is None and _timed_out(reply) and reach.resend():
                    lost = True
                    continue
                ok = reply.ok
                if ok is not None and ok.encoding == self._result_enc:
                    # the server held the query (it accepted the goal): the acceptance came first,
                    # or rides on this result (a goal that ended before it was sent)
                    stamp = None if first is not None else accepted_stamp(ok)
                    if h is None and (first is not None or stamp is not None):
                        done = self._quick_result(gid, ok)
                        if done is not None:
                            return done
                    if h is None:  # replay the acceptance to a handle made now
                        h = self._register(gid, goal, None)
                        if first is not None:
                            self._on_send_reply(h, first, wait)
                    if stamp is not None:
                        self._accept(h, stamp, reply)
                    self._on_result_reply(h, reply, False)
                    break
                if first is None:
                    first = reply
                    if h is not None:
                        self._on_send_reply(h, reply, wait)
            else:  # the query ended without the result
                if lost:  # lost on the way (or the server is slow): the goal again, same id
                    continue
                pause = None if first is not None else reach.again()
                if pause is not None:  # no answer at all, but the graph lists a server
                    time.sleep(pause)
                    continue
                if h is None or first is None:  # the answer (if any) is not yet on a handle
                    h = h or self._register(gid, goal, None)
                    self._on_send_reply(h, first, wait)
                if h.accepted and not h.done:
                    self._request_result(h)  # a long goal: ask for its result
            break
        if timeout is None:
            return h.result()
        try:
            return h.result(max(0.0, timeout - (time.monotonic() - start)))
        except ZenrosTimeout:
            if h.done:  # the goal failed with a timeout of its own (no answer)
                raise
            raise ZenrosTimeout(f"goal {h.goal_id} on {self.name} did not end within "
                                f"{timeout:g} s (status {h.status.name})") from None

    def _quick_result(self, gid: uuid.UUID, ok: zenoh.Sample) -> GoalResult[R] | None:
        """The result a held send_goal query carried, or None if it does not decode."""
        try:
            res = self._gr_res.decode(ok.payload.to_bytes())
        except CodecError:
            return None  # the handle path reports it
        return GoalResult(gid, _status(res.status), res.result)

    def send_goal_async(self, goal: G, feedback_callback: Callable[[Any], Any] | None = None
                        ) -> ClientGoalHandle[G, R]:
        """Send ``goal`` and return its handle at once.

        ``feedback_callback(msg)`` gets each ``<Name>_FeedbackMessage`` (``msg.feedback``,
        ``msg.goal_id``) in order, and before the goal's end is reported; a plain function runs
        on the client's feedback thread, an ``async def`` one on the node's event loop.

        Raises:
            EncodeError: ``goal`` is not the action's Goal type.
        """
        handle, data = self._new_goal(goal, feedback_callback)
        self._send(handle, data)
        return handle

    def _new_goal(self, goal: G, feedback_callback: Callable[[Any], Any] | None,
                  ) -> tuple[ClientGoalHandle[G, R], bytes]:
        """A registered handle for a new goal and its encoded send_goal request."""
        gid, data = self._encode_goal(goal)
        return self._register(gid, goal, feedback_callback), data

    def _encode_goal(self, goal: Any) -> tuple[uuid.UUID, bytes]:
        """A fresh goal id and the encoded send_goal request (checks type and client)."""
        if type(goal) is not self.action_type.Goal:
            raise EncodeError(f"action {self.name} takes {codec_for(self.action_type.Goal).type_name}"
                              f" goals, got {type(goal).__name__}")
        if self.closed:
            raise ActionError(f"action client {self.name} is closed")
        gid = uuid.uuid4()
        return gid, self._sg_req.encode(self._wire.SendGoalRequest(goal_id=uuid_msg(gid),
                                                                   goal=goal))

    def _register(self, gid: uuid.UUID, goal: G,
                  feedback_callback: Callable[[Any], Any] | None) -> ClientGoalHandle[G, R]:
        """A handle for goal ``gid``, known to this client until the goal ends."""
        dispatch = None if feedback_callback is None else make_dispatch(
            feedback_callback, executor=self._ctx.executor, logger=self.logger,
            what=f"feedback of {self.name}", depth=100)
        handle: ClientGoalHandle[G, R] = ClientGoalHandle(self, gid, goal, dispatch,
                                                          self._ctx.executor, self._inbox)
        with self._lock:
            self._handles[handle.key] = handle
        return handle

    def _send(self, h: ClientGoalHandle, data: bytes) -> None:
        """One query for the goal and its result: the server replies the acceptance at once
        and (asked by the attachment) the result when the goal ends. A goal still running
        when the query times out (``send_timeout``) gets its result by get_result requests.
        A query no server answered is sent again while the graph lists one (`Reach`)."""
        reach = Reach(self.server_is_ready, self.send_timeout, self.reach_grace, RELINK)
        self._send_once(h, data, reach)

    def _send_once(self, h: ClientGoalHandle, data: bytes, reach: Reach) -> None:
        if h.done:  # closed meanwhile
            return
        state = {"answered": False, "result": False, "timed_out": False}

        def on_reply(reply: zenoh.Reply) -> None:
            ok = reply.ok
            if not state["answered"] and _timed_out(reply) and reach.resend():
                state["timed_out"] = True  # lost on the way: on_final sends it again
                return
            if ok is not None and ok.encoding == self._result_enc:
                state["result"] = True
                if not state["answered"]:
                    stamp = accepted_stamp(ok)
                    if stamp is not None:  # the acceptance rides on the result
                        state["answered"] = True
                        self._accept(h, stamp, reply)
                self._on_result_reply(h, reply, False)
            elif not state["answered"]:
                state["answered"] = True
                self._on_send_reply(h, reply)
            # else: the query timed out after the acceptance; on_final asks for the result

        def on_final() -> None:
            if not state["answered"] and state["timed_out"] and not self.closed:
                self._later(0.0, self._send_once, h, data, reach)
                return
            if not state["answered"]:
                pause = None if self.closed else reach.again()
                if pause is not None:  # not from here: a Zenoh thread must not query
                    self._later(pause, self._send_once, h, data, reach)
                    return
                state["answered"] = True
                self._on_send_reply(h, None)
            elif not state["result"] and h.accepted and not h.done:
                self._request_result_soon(h)

        query_replies(self._ctx.session, self._send_key, data, self._enc["send_goal"],
                      reach.attempt(), on_reply, on_final, RESULT_ON_GOAL,
                      self._ctx.destination(self._keys["send_goal"]))

    def forget(self, handle: ClientGoalHandle) -> None:
        """A goal ended (its handle says so): stop following it."""
        with self._lock:
            self._handles.pop(handle.key, None)
            self._absent_since.pop(handle.key, None)

    def _get(self, part: str, payload: bytes, timeout: float,
             done: Callable[[zenoh.Reply | None], None]) -> None:
        key = self._keys[part]
        query_once(self._ctx.session, key, payload, self._enc[part], timeout, done,
                   self._ctx.destination(key))

    def _accept(self, h: ClientGoalHandle, stamp: Time, reply: zenoh.Reply) -> None:
        """The acceptance a result reply carried (its result follows at once)."""
        rid = reply.replier_id
        h.set_accepted(True, stamp, "", str(rid.zid) if rid else "")

    def _on_send_reply(self, h: ClientGoalHandle, reply: zenoh.Reply | None,
                       waited: float | None = None) -> None:
        if reply is None:
            h.set_exception(None, ActionServerUnavailableError(
                f"no action server answered goal {h.goal_id} on {self.name}"))
            return
        if reply.ok is None:
            assert reply.err is not None
            kind, message = parse_error(reply.err.payload.to_bytes())
            if kind == "Timeout":
                waited = self.send_timeout if waited is None else waited
                h.set_exception(None, ZenrosTimeout(
                    f"action {self.name} did not answer goal {h.goal_id} within {waited:g} s"))
            else:
                h.set_exception(GoalStatus.REJECTED, GoalRejectedError(
                    f"action {self.name} refused goal {h.goal_id}: {message}"), message)
            return
        try:
            res = self._sg_res.decode(reply.ok.payload.to_bytes())
        except CodecError as exc:
            h.set_exception(None, ActionError(f"action {self.name}: bad send_goal response: {exc}"))
            return
        rid = reply.replier_id
        if h.set_accepted(res.accepted, res.stamp, res.reason, str(rid.zid) if rid else ""):
            self._request_result_soon(h)

    # ------------------------------------------------------------------ results

    def _request_result(self, h: ClientGoalHandle) -> None:
        if h.done or self.closed:
            return
        data = self._gr_req.encode(self._wire.GetResultRequest(goal_id=uuid_msg(h.goal_id)))
        early = h.accepted is None
        self._get("get_result", data, self.result_timeout,
                  lambda reply: self._on_result_reply(h, reply, early))

    def _request_result_soon(self, h: ClientGoalHandle, delay: float = 0.0) -> None:
        """`_request_result` from the executor: reply callbacks run on Zenoh's own threads,
        where a new query could deadlock (found with a router between the peers)."""
        if delay <= 0:
            self._ctx.executor.call_soon(self._request_result, h)
        else:
            self._later(delay, self._request_result, h)

    def _on_result_reply(self, h: ClientGoalHandle, reply: zenoh.Reply | None,
                         early: bool) -> None:
        if h.done:
            return
        if reply is not None and reply.ok is not None:
            try:
                res = self._gr_res.decode(reply.ok.payload.to_bytes())
            except CodecError as exc:
                h.set_exception(None, ActionError(f"action {self.name}: bad result for goal "
                                          f"{h.goal_id}: {exc}"))
                return
            h.set_result(_status(res.status), res.result)
            return
        kind, message = ("", "") if reply is None or reply.err is None else \
            parse_error(reply.err.payload.to_bytes())
        if kind == "GoalRejected":
            h.set_exception(GoalStatus.REJECTED, GoalRejectedError(
                f"action {self.name} rejected goal {h.goal_id}: {message}"), message)
        elif early and kind in ("UnknownGoal", ""):
            # The pipelined request overtook the goal: ask again once the goal is accepted.
            if not h.defer_result_request():
                self._request_result_soon(h)
        elif kind == "UnknownGoal":
            h.set_result(GoalStatus.LOST, self.action_type.Result(), message)
        elif kind == "Timeout":
            self._retry_or_lose(h)
        elif not kind:
            self._retry_or_lose(h, delay=0.1)
        else:
            h.set_exception(None, ActionError(f"action {self.name}: result of goal {h.goal_id}: "
                                      f"{message}"))

    def _retry_or_lose(self, h: ClientGoalHandle, delay: float = 0.0) -> None:
        """No result yet (query timed out, or no server answered): ask again, at once if the
        server that took the goal is there, else once it is back (`_await_server`)."""
        if self._server_alive(h):
            self._request_result_soon(h, delay)
        else:
            self._await_server(h)

    def _server_alive(self, h: ClientGoalHandle) -> bool:
        servers = self._graph.action_servers(self.name)
        return any(t.zid == h.server_zid for t in servers) if h.server_zid else bool(servers)

    def _await_server(self, h: ClientGoalHandle) -> None:
        """The goal's server is not in the graph: look again every `ABSENT_POLL` seconds; ask
        for the result once it is back, report the goal LOST if it stays away for
        `lost_timeout` seconds. One look-out per goal at a time."""
        with self._lock:
            if h.key in self._absent_since:
                return
            self._absent_since[h.key] = time.monotonic()
        self._later(ABSENT_POLL, self._look_for_server, h)

    def _look_for_server(self, h: ClientGoalHandle) -> None:
        if h.done or self.closed:
            return
        since = self._absent_since.get(h.key)
        if since is None:  # ended meanwhile (forget)
            return
        if self._server_alive(h):
            with self._lock:
                self._absent_since.pop(h.key, None)
            self._request_result(h)
        elif time.monotonic() - since >= self.lost_timeout:
            self._lose(h)
        else:
            self._later(ABSENT_POLL, self._look_for_server, h)

    def _later(self, delay: float, fn: Callable[..., object], *args: Any) -> None:
        """Run ``fn(*args)`` on the executor's loop ``delay`` seconds from now (from any
        thread)."""
        ex = self._ctx.executor
        ex.call_soon(ex.loop.call_later, delay, fn, *args)

    def _lose(self, h: ClientGoalHandle) -> None:
        h.set_result(GoalStatus.LOST, self.action_type.Result(),
                  f"action server {self.name} went away while goal {h.goal_id} was "
                  f"{h.status.name}")

    def _on_graph(self, event: str, tok: Token) -> None:
        """A server token went away: its goals wait for it to come back (`_await_server`). A
        killed or cut-off server is usually noticed sooner, by the result request it leaves
        unanswered."""
        if self.closed or event != "delete" or tok.kind != "act" or tok.name != self.name:
            return
        with self._lock:
            handles = [h for h in self._handles.values() if h.accepted and not h.done]
        for h in handles:
            if not self._server_alive(h):
                self._await_server(h)

    # ------------------------------------------------------------------ topics

    def _on_feedback(self, sample: zenoh.Sample) -> None:
        if misrouted(sample.attachment, self._tags["feedback"]):
            self._bad_sample("feedback", "published on another key (Zenoh misrouted it; "
                                         "docs/wire.md)", sample)
            return
        if sample.encoding != self._fb_enc:  # another type (a wrong publisher) says so here
            schema = split_encoding(str(sample.encoding))[1]
            if schema and normalize_type_name(schema) != self._fb.type_name:
                self._bad_sample("feedback", f"type mismatch: expected {self._fb.type_name}, "
                                             f"got {schema}", sample)
                return
        try:
            msg = self._fb.decode(sample.payload.to_bytes())
        except CodecError as exc:
            self._bad_sample("feedback", exc, sample)
            return
        h = self._handles.get(bytes(msg.goal_id.uuid))
        if h is not None and h.wants_feedback:
            self._inbox.put(lambda: h.deliver_feedback(msg))

    def _on_status(self, sample: zenoh.Sample) -> None:
        if misrouted(sample.attachment, self._tags["status"]):
            self._bad_sample("status", "published on another key (Zenoh misrouted it; "
                                       "docs/wire.md)", sample)
            return
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
                    h.advance(GoalStatus(st.status))

    def _bad_sample(self, part: str, exc: Exception | str,
                    sample: zenoh.Sample | None = None) -> None:
        if self._throttle.allow(part):
            self.logger.error("action %s: cannot decode %s%s: %s", self.name, part,
                              self._sender(sample), exc)

    def _sender(self, sample: zenoh.Sample | None) -> str:
        """`` from <nodes>`` behind a sample's session (who published a bad sample)."""
        ts = None if sample is None else sample.timestamp
        if ts is None:
            return ""
        zid = str(ts.get_id())
        nodes = self._graph.nodes_of_zid(zid)
        return f" from {', '.join(nodes) if nodes else f'session {zid}'}"

    # ------------------------------------------------------------------ cancel

    def cancel_all_goals(self, timeout: float = 5.0) -> list[uuid.UUID]:
        """Cancel every goal of the server (any client's); return the goals now canceling."""
        return self._cancel(ZERO_UUID, Time(), timeout)

    def cancel_goals_before(self, stamp: Time, timeout: float = 5.0) -> list[uuid.UUID]:
        """Cancel every goal the server accepted at or before ``stamp``."""
        return self._cancel(ZERO_UUID, stamp, timeout)

    def cancel_goal(self, goal_id: uuid.UUID, timeout: float = 5.0) -> list[uuid.UUID]:
        """Ask the server to cancel goal ``goal_id`` (`ClientGoalHandle.cancel`); return the
        goals now canceling."""
        return self._cancel(goal_id, Time(), timeout)

    def _cancel(self, goal_id: uuid.UUID, stamp: Time, timeout: float) -> list[uuid.UUID]:
        key = self._keys["cancel_goal"]
        return request_cancel(self._ctx.session, key, self.name, goal_id, stamp, timeout,
                              self._ctx.destination(key), Reach(self.server_is_ready, timeout,
                                                                self.reach_grace, RELINK))

    # ------------------------------------------------------------------ lifecycle

    def close(self) -> None:
        """Undeclare the subscriptions; goals still waiting for an end fail with ActionError."""
        if self.closed:
            return
        self.closed = True
        self._unlisten()
        self._token.undeclare()
        self._fb_sub.undeclare()
        self._status_sub.undeclare()
        with self._lock:
            handles = list(self._handles.values())
        for h in handles:
            h.set_exception(None, ActionError(f"action client {self.name} closed before goal "
                                      f"{h.goal_id} ended"))
        self._inbox.close()

    def __repr__(self) -> str:
        return f"<ActionClient {self.name} [{self.action_type.name}]>"


def _timed_out(reply: zenoh.Reply | None) -> bool:
    """Whether ``reply`` is Zenoh's own: the query timed out with no answer from a server."""
    return (reply is not None and reply.err is not None
            and parse_error(reply.err.payload.to_bytes())[0] == "Timeout")


def _status(value: int) -> GoalStatus:
    try:
        return GoalStatus(value)
    except ValueError:
        return GoalStatus.UNKNOWN


