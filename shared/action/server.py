"""`ActionServer`: serves one action: the send_goal, cancel_goal and get_result requests, and
the feedback and status topics; a `GoalRunner` runs the goals."""

from __future__ import annotations

import inspect
import logging
import threading
import time
from collections.abc import Awaitable, Callable
from typing import Any, Generic

import zenoh

from ..codec import codec_for
from ..context import is_session_failure
from ..errors import EncodeError, GoalRejectedError
from ..keytag import key_tag
from ..log import ErrorLog
from ..message import ActionType, F, G, R
from ..qos import QoSProfile
from ..rpc import wildcard_refusal
from ..service_events import ServiceIntrospectionState
from .goal_handle import ServerGoalHandle
from .goals import GoalTable
from .host import ActionHost
from .introspection import ActionEvents
from .leaders import QueryQueue, RequestThreads
from .policies import GoalPolicy
from .runner import GoalRunner
from .status import StatusPublisher
from .transport import (
    RESULT_ON_GOAL,
    accepted_attachment,
    answer,
    answer_err,
    decode_query,
    encoding_for,
)
from .types import (
    ZERO_UUID,
    CancelCode,
    CancelGoalRequest,
    CancelGoalResponse,
    CancelResponse,
    GoalResponse,
    GoalStatus,
    uuid_from_msg,
)
from .wire import wire_types

__all__ = ["ActionServer"]

Handle = ServerGoalHandle[Any]
_ZERO_KEY = bytes(16)
QUERY_QUEUE = 256  # requests buffered before Zenoh pushes back


class ActionServer(Generic[G, R, F]):
    """Serves ``name`` with ``action_type`` (goals of type G, results of type R, feedback of
    type F: `Node.create_action_server` infers them from ``action_type``).

    Args:
        node: the node that owns the server (closing the node closes it).
        action_type: e.g. ``example_interfaces.Fibonacci``.
        name: the action name, resolved like a topic name.
        execute_callback: ``execute(goal_handle) -> Result``, plain (run on a worker thread) or
            ``async def`` (run on the node's event loop). It ends the goal with
            ``goal_handle.succeed()``, ``abort()`` or ``canceled()``; if it returns without one,
            the goal ends CANCELED when a cancel was requested and ABORTED otherwise (rclpy
            aborts), with a warning.
        goal_callback: ``goal_callback(goal) -> GoalResponse | bool``, a plain function run on
            the thread that receives requests; raise `GoalRejectedError` to reject with a
            reason. Default: accept.
        cancel_callback: ``cancel_callback(goal_handle) -> CancelResponse | bool``, a plain
            function. Default: accept (rclpy's default rejects).
        policy: a `GoalPolicy` or its name (``simple``, ``queue``, ``queue:<max_waiting>``,
            ``reject_if_busy``, ``parallel``, ``parallel:<n>``).
        result_timeout: seconds a result stays available after its goal ended (ROS 2: 900).
        status_history: how many ended goals the status array keeps listing.
        shutdown_timeout: seconds `close` waits for running goals after canceling them.
    """

    def __init__(
        self,
        node: ActionHost,
        action_type: ActionType[G, R, F],
        name: str,
        execute_callback: Callable[[ServerGoalHandle[G, F]], R | None | Awaitable[R | None]],
        goal_callback: Callable[[G], GoalResponse | bool] | None = None,
        cancel_callback: Callable[[ServerGoalHandle[G, F]], CancelResponse | bool] | None = None,
        *,
        policy: str | GoalPolicy = "simple",
        result_timeout: float = 900.0,
        status_history: int = 16,
        shutdown_timeout: float = 2.0,
    ) -> None:
        for label, fn in (("goal_callback", goal_callback), ("cancel_callback", cancel_callback)):
            if fn is not None and inspect.iscoroutinefunction(fn):
                raise TypeError(f"{label} must be a plain function (it decides at once); "
                                "only execute_callback may be async")
        self.action_type = action_type
        self.name = node.resolve_name(name, "action")
        self.policy = GoalPolicy.parse(policy)
        self.logger = node.logger
        self.shutdown_timeout = shutdown_timeout
        self._node = node
        self._ctx = ctx = node.context
        self._goal_cb = goal_callback
        self._cancel_cb = cancel_callback
        self._wire = wire = wire_types(action_type)
        self._sg_req, self._sg_res, self._gr_req, self._gr_res, self._fb = wire.codecs()
        self._cg_req = codec_for(CancelGoalRequest)
        self._cg_res = codec_for(CancelGoalResponse)
        self._enc = {t: encoding_for(t) for t in (wire.SendGoalResponse, wire.GetResultResponse,
                                                  CancelGoalResponse)}
        self.lock = threading.RLock()  # the server's table and every goal's state (GoalHost)
        self._errors = ErrorLog(self.logger)
        self._table = GoalTable(result_timeout, status_history)
        s, key = ctx.session, self._key
        self._status = StatusPublisher(s, key("status"), ctx.executor, self._table.status_list,
                                       self.lock)
        self._runner = GoalRunner(
            self.name, action_type, execute_callback,
            inspect.iscoroutinefunction(execute_callback), self.policy, self._table,
            self._status, self.lock, ctx.executor, self.logger, self._deliver)
        self._closing = False
        self.closed = False
        self._fb_tag = key_tag(key("feedback"))
        self._fb_pub: Any = s.declare_publisher(
            key("feedback"), encoding=encoding_for(wire.FeedbackMessage),
            congestion_control=zenoh.CongestionControl.BLOCK)
        # One queryable for the three request keys, served from a channel by one thread at a
        # time: the requests are handled in arrival order (a client may send get_result right
        # behind send_goal), and Zenoh queues them without taking the GIL (as services do).
        # A goal with a plain execute callback runs on the thread that accepted it; one still
        # running after DETACH_DELAY hands the channel to another request thread (leaders.py).
        self._gate = getattr(node, "_setup_gate", None)  # requests wait until setup() returned
        self._handlers = {"send_goal": self._on_send_goal, "cancel_goal": self._on_cancel,
                          "get_result": self._on_get_result}
        self._parts = {key(p): p for p in self._handlers}  # exact keys only: no wildcards
        requests = QueryQueue(QUERY_QUEUE)  # its threads wait without waking (leaders.py)
        self._queryable: Any = s.declare_queryable(key("*"), requests.handler, complete=True)
        self._job: Handle | None = None  # the goal the leading request thread runs next
        self._threads = RequestThreads(f"zenros-action:{self.name}", requests,
                                       self._on_request, self._runner.run, self._settle,
                                       self._on_failure, self.logger)
        self._threads.start()
        self._unserve = ctx.serve_here(*self._parts)
        self.events = ActionEvents.of(ctx, node.fqn, action_type, self.name)
        """Its introspection events (`zenros.action.introspection`), off until configured."""
        self._result_seqs: dict[int, int] = {}  # get_result queries waiting: their event seq
        self._status.flush(force=True)
        self._token: Any = s.liveliness().declare_token(ctx.keys.entity_token(
            "act", node.fqn, self.name, action_type.name, "", ctx.zid, ctx.next_eid()))
        node.add_waitable(self)

    def _key(self, part: str) -> str:
        return self._ctx.keys.action(self.name, part)

    def configure_introspection(self, clock: Any, qos: QoSProfile | None,
                                state: ServiceIntrospectionState) -> None:
        """rclpy's (Kilted): publish the requests and responses of the action's three
        services on ``<name>/_action/<service>/_service_event`` (METADATA: the info alone;
        CONTENTS: the messages too; OFF: nothing). ``zenros action echo`` shows them."""
        self.events.configure(clock, qos, state)

    def _goal_decided(self, seq: int, accepted: bool, reason: str, stamp: Any = None) -> None:
        if seq:
            res = self._wire.SendGoalResponse(accepted=accepted, reason=reason)
            if stamp is not None:
                res.stamp = stamp
            self.events.send_goal.response(seq, res)

    def _on_request(self, query: zenoh.Query) -> Handle | None:
        """Handle one request (on the leading request thread); return the goal this thread
        runs now, if the request started one."""
        gate = self._gate
        if gate is not None and not gate.is_open:
            gate.wait()
        self._on_query(query)
        h, self._job = self._job, None
        return h

    def _on_failure(self, exc: BaseException) -> None:
        if not is_session_failure(exc):
            raise exc
        self._ctx.fail(exc)  # the process exits (runtime) so supervision can restart it

    @property
    def errors(self) -> int:
        """Requests answered with an error (bad requests, internal failures)."""
        return self._errors.count

    def _on_query(self, query: zenoh.Query) -> None:
        """Route one request; whatever it does, it is answered and the server keeps serving.
        A request is finalized here unless its handler holds it: a get_result (or a send_goal
        that asked for its result) waiting for its goal's end, which `_deliver` answers."""
        part = ""
        held = False
        try:
            key = str(query.key_expr)
            part = self._parts.get(key, "")
            handler = self._handlers.get(part)
            if not part and ("*" in key or "$" in key):  # a wildcard is refused
                part = ""
                self._reply_err(query, "BadRequest", wildcard_refusal(
                    f"action {self.name}", self._key("<request>"), query))
            elif handler is not None:
                held = handler(query) is True
            else:
                self._reply_err(query, "BadRequest", f"action {self.name}: no request "
                                f"{key.rsplit('/', 1)[-1]!r}; valid: "
                                f"{', '.join(self._handlers)}")
        except Exception as exc:  # noqa: BLE001 nothing a request does stops the server
            self._errors.report("InternalError", logging.ERROR,
                                "action %s: %s request failed: %s: %s", self.name, part or "a",
                                type(exc).__name__, exc, exc_info=exc)
            try:
                answer_err(query, "InternalError", f"{type(exc).__name__}: {exc}")
            except zenoh.ZError:  # already answered or finalized
                pass
        finally:
            if not held:
                query.drop()  # type: ignore[no-untyped-call]

    def _reply_err(self, query: zenoh.Query, kind: str, message: str) -> None:
        if kind == "BadRequest":
            self._errors.report(kind, logging.WARNING, "%s", message)
        answer_err(query, kind, message)

    # ------------------------------------------------------------------ send_goal

    def _on_send_goal(self, query: zenoh.Query) -> bool | None:
        """Admit a goal; True if ``query`` is held to carry the goal's result too."""
        req = decode_query(query, self._sg_req, f"action {self.name} send_goal")
        if isinstance(req, str):
            self._reply_err(query, "BadRequest", req)
            return None
        seq = 0
        if self.events.on:
            seq = self.events.send_goal.next_sequence()
            self.events.send_goal.request(seq, req)
        key = bytes(req.goal_id.uuid)  # the codec checked 16 numbers of 0-255
        if key == _ZERO_KEY:
            self._reply_err(query, "BadRequest", f"action {self.name} send_goal: "
                            "goal_id must be a non-zero UUID")
            return None
        handle: Handle = ServerGoalHandle(self, key, req.goal, req.goal_id)
        with self.lock:  # registered at once: a get_result right behind it will wait
            fresh = not self._closing and self._table.add_pending(handle)
            prior = None if fresh or self._closing else self._table.lookup(key)
            if (prior is not None and prior.status is not GoalStatus.UNKNOWN
                    and prior.request == req.goal):
                return self._answer_again(query, prior, seq)
        if not fresh:
            why = ("server is shutting down" if self._closing
                   else f"duplicate goal id {handle.goal_id}")
            self._goal_decided(seq, False, why)
            self._respond(query, False, why)
            return None
        reason = self._ask_goal_callback(req.goal)
        with self.lock:
            if not reason and self._closing:
                reason = "server is shutting down"
            plan = None if reason else self._runner.sched.offer(handle.key)
            if plan is None or plan.reject:
                reason = reason or (plan.reject if plan else "")
                self._table.remove(handle)
                for w in handle.take_waiters():
                    self._reply_err(w, "GoalRejected", reason)
                self._goal_decided(seq, False, reason)
                self._respond(query, False, reason)
                return None
            handle.accept_at(self._node.now())
            self._goal_decided(seq, True, "", handle.stamp)
            launch = self._runner.accept(handle, plan)
            hold = _wants_result(query)  # the client asked for the result on this query too
            if (self._runner.on_workers and handle in launch
                    and len(self._runner.sched.running) == 1):
                # The only running goal runs on this thread, right after this request (a
                # burst of goals still goes to workers: see leaders.py).
                launch.remove(handle)
                self._job = handle
            if hold and self._job is handle:
                # Its acceptance is held back: it rides on the result reply if the goal ends
                # within DETACH_DELAY (one message instead of two), else it is sent when the
                # goal is detached; feedback sends it first.
                handle.owe_acceptance(query)
            else:
                try:
                    self._respond(query, True, "", handle, finalize=not hold)
                except zenoh.ZError as exc:  # the client is gone (closed, timed out): the
                    # goal was accepted all the same and runs (launched below), as in _settle
                    self.logger.debug("action %s: acceptance of goal %s not sent: %s",
                                      self.name, handle.goal_id, exc)
                    hold = False
                if hold:
                    if not handle.has_result:
                        handle.add_waiter(query)
                    else:  # the plan already ended it (a queue that dropped it)
                        self._answer_result(query, handle)
            self._runner.launch(launch)
            return hold

    def _answer_again(self, query: zenoh.Query, h: Handle, seq: int) -> bool | None:
        """The goal ``h`` sent again, the same goal under the same id: its client lost the
        first answer (a link that dropped and was made again ends the queries it carried,
        unanswered) and asked again (`zenros.reach`). It is answered as it was: accepted, then
        its result on the same query if the client asks for it, now or when it ends. Called
        with the lock held; True if ``query`` is held."""
        self._goal_decided(seq, True, "", h.stamp)
        hold = _wants_result(query)
        try:
            if hold and h.has_result:  # one reply: the result, the acceptance attached
                answer(query, self._result_payload(h), self._enc[self._wire.GetResultResponse],
                       accepted_attachment(h.stamp))
                return None
            self._respond(query, True, "", h, finalize=not hold)
        except (zenoh.ZError, RuntimeError) as exc:  # this client is gone too
            self.logger.debug("action %s: acceptance of goal %s not sent again: %s",
                              self.name, h.goal_id, exc)
            return None
        if hold:
            h.add_waiter(query)
        return hold

    def _ask_goal_callback(self, goal: Any) -> str:
        """'' to accept, else the rejection reason."""
        if self._goal_cb is None:
            return ""
        try:
            verdict = self._goal_cb(goal)
        except GoalRejectedError as exc:
            return str(exc) or "rejected by the goal callback"
        except Exception as exc:
            self.logger.exception("action %s: goal callback raised", self.name)
            return f"goal callback raised {type(exc).__name__}: {exc}"
        if verdict is GoalResponse.ACCEPT or verdict is True:
            return ""
        return "rejected by the goal callback"

    def _settle(self, h: Handle) -> None:
        """Send ``h``'s acceptance if it still owes it. Takes the lock: the watchdog (a goal
        past DETACH_DELAY), the goal's own thread (its first feedback) and `_deliver` (its
        result) may each reach for the owed query, and zenoh-python refuses a second thread
        on a query in use ("Already borrowed": seen beside a CPU hog, where it left a
        preempted goal in the schedule and the next goal never started)."""
        if not h.owes_acceptance:  # the usual case, feedback after the acceptance: no lock
            return
        with self.lock:
            query = h.take_owed()
            if query is not None:
                try:
                    self._respond(query, True, "", h, finalize=False)
                except (zenoh.ZError, RuntimeError) as exc:  # the query is gone (client
                    # closed, timed out) or refused: the goal runs on, its result still goes
                    self.logger.debug("action %s: acceptance of goal %s not sent: %s: %s",
                                      self.name, h.goal_id, type(exc).__name__, exc)

    def _respond(self, query: zenoh.Query, accepted: bool, reason: str,
                 handle: Handle | None = None, finalize: bool = True) -> None:
        res = self._wire.SendGoalResponse(accepted=accepted, reason=reason)
        if accepted and handle is not None:
            res.stamp = handle.stamp
        data, enc = self._sg_res.encode(res), self._enc[self._wire.SendGoalResponse]
        if finalize:
            answer(query, data, enc)
        else:
            query.reply(query.key_expr, data, encoding=enc)

    def cancel_all_goals(self) -> int:
        """Cancel every goal this server holds, from the server's side (as a node being
        deactivated does; the cancel callback is not asked): running goals are asked to
        cancel, waiting ones end CANCELED. The number of goals asked."""
        with self.lock:
            handles = list(self._table.active.values())
            for h in handles:
                self._runner.request_cancel(h)
            if handles:
                self._status.mark()
        return len(handles)

    # ------------------------------------------------------------------ cancel_goal

    def _on_cancel(self, query: zenoh.Query) -> None:
        req = decode_query(query, self._cg_req, f"action {self.name} cancel_goal")
        if isinstance(req, str):
            return self._reply_err(query, "BadRequest", req)
        seq = 0
        if self.events.on:
            seq = self.events.cancel_goal.next_sequence()
            self.events.cancel_goal.request(seq, req)
        gid = uuid_from_msg(req.goal_info.goal_id)
        key = None if gid == ZERO_UUID else gid.bytes
        stamp = req.goal_info.stamp
        stamp_ns = stamp.sec * 1_000_000_000 + stamp.nanosec
        with self.lock:
            targets = list(self._table.cancel_targets(key, stamp_ns))
            state = self._table.terminal_or_unknown(key) if key else GoalStatus.UNKNOWN
        if key is not None and stamp_ns == 0 and not targets:
            code = (CancelCode.ERROR_UNKNOWN_GOAL_ID if state is GoalStatus.UNKNOWN
                    else CancelCode.ERROR_GOAL_TERMINATED)
            return self._reply_cancel(query, code, [], seq)
        accepted = [h for h in targets
                    if h.status is GoalStatus.CANCELING or self._ask_cancel_callback(h)]
        with self.lock:
            for h in accepted:
                self._runner.request_cancel(h)
        code = CancelCode.ERROR_REJECTED if targets and not accepted else CancelCode.ERROR_NONE
        self._reply_cancel(query, code, accepted, seq)

    def _ask_cancel_callback(self, h: Handle) -> bool:
        if self._cancel_cb is None:
            return True
        try:
            verdict = self._cancel_cb(h)
        except Exception:
            self.logger.exception("action %s: cancel callback raised; rejecting", self.name)
            return False
        return verdict is CancelResponse.ACCEPT or verdict is True

    def _reply_cancel(self, query: zenoh.Query, code: CancelCode, goals: list[Handle],
                      seq: int = 0) -> None:
        res = CancelGoalResponse(return_code=int(code), goals_canceling=[h.info for h in goals])
        if seq:
            self.events.cancel_goal.response(seq, res)
        answer(query, self._cg_res.encode(res), self._enc[CancelGoalResponse])

    # ------------------------------------------------------------------ get_result

    def _on_get_result(self, query: zenoh.Query) -> bool | None:
        req = decode_query(query, self._gr_req, f"action {self.name} get_result")
        if isinstance(req, str):
            self._reply_err(query, "BadRequest", req)
            return None
        seq = 0
        if self.events.on:
            seq = self.events.get_result.next_sequence()
            self.events.get_result.request(seq, req)
        gid = uuid_from_msg(req.goal_id)
        with self.lock:
            if self._table.expire(time.monotonic()):
                self._status.mark()
            h = self._table.lookup(gid.bytes)
            if h is not None and not h.has_result:
                h.add_waiter(query)  # answered when the goal's result is set
                if seq:
                    self._result_seqs[id(query)] = seq
                return True
            data = None if h is None else self._result_payload(h)
        if data is not None:
            if seq and h is not None:
                self._result_event(seq, h)
            answer(query, data, self._enc[self._wire.GetResultResponse])
            return None
        self._reply_err(query, "UnknownGoal", (
            f"action {self.name}: unknown goal id {gid}: it was never accepted by this server, "
            f"or its result expired (results are kept {self._table.result_timeout:g} s)"))
        return None

    def _result_event(self, seq: int, h: Handle) -> None:
        self.events.get_result.response(
            seq, self._wire.GetResultResponse(status=int(h.status), result=h.result))

    def _result_payload(self, h: Handle) -> bytes:
        res = self._wire.GetResultResponse(status=int(h.status), result=h.result)
        return self._gr_res.encode(res)

    def _answer_result(self, query: zenoh.Query, h: Handle) -> None:
        answer(query, self._result_payload(h), self._enc[self._wire.GetResultResponse])

    def _deliver(self, h: Handle, waiters: list[zenoh.Query]) -> None:
        """Answer the result requests that waited on ``h`` (its result was just set). A
        send_goal query still owed its acceptance gets one reply: the result, with the
        acceptance in its attachment."""
        data = self._result_payload(h)
        enc = self._enc[self._wire.GetResultResponse]
        owed = h.take_owed()
        for w in waiters:
            seq = self._result_seqs.pop(id(w), 0) if self._result_seqs else 0
            if seq:
                self._result_event(seq, h)
            try:
                answer(w, data, enc, accepted_attachment(h.stamp) if w is owed else None)
            except (zenoh.ZError, RuntimeError) as exc:  # one request gone (its client
                # closed or timed out) never keeps the others, or the goal's end, waiting
                self.logger.warning("action %s: result of goal %s not sent to a request: "
                                    "%s: %s", self.name, h.goal_id, type(exc).__name__, exc)

    # ------------------------------------------------------------------ GoalHost (the handles)

    def goal_changed(self) -> None:
        self._status.mark()

    def encode_feedback(self, handle: Handle, feedback: Any) -> bytes:
        if type(feedback) is not self.action_type.Feedback:
            raise EncodeError(f"action {self.name} feedback is "
                              f"{codec_for(self.action_type.Feedback).type_name}, "
                              f"got {type(feedback).__name__}")
        data: bytes = self._fb.encode(self._wire.FeedbackMessage(
            goal_id=handle.info.goal_id, feedback=feedback))
        return data

    def put_feedback(self, handle: Handle, data: bytes) -> None:
        if not self.closed:
            self._settle(handle)  # the client hears of the goal before its feedback
            self._fb_pub.put(data, attachment=self._fb_tag)

    # ------------------------------------------------------------------ lifecycle

    def close(self) -> None:
        """Stop taking goals, cancel the running ones, wait ``shutdown_timeout`` for them, abort
        what is left (answering every pending result request), then undeclare everything."""
        with self.lock:
            if self._closing:
                return
            self._closing = True
        self._runner.shutdown(self.shutdown_timeout)
        with self.lock:
            self.closed = True
        self._unserve()
        self._token.undeclare()
        self._queryable.undeclare()
        self._threads.join(2.0)
        self._fb_pub.undeclare()
        self._status.close()
        self.events.close()
        self._result_seqs.clear()

    def __repr__(self) -> str:
        return f"<ActionServer {self.name} [{self.action_type.name}] policy={self.policy}>"


def _wants_result(query: zenoh.Query) -> bool:
    """True if a send_goal asks for its result on the same query (`RESULT_ON_GOAL`)."""
    att = query.attachment
    return att is not None and att.to_bytes() == RESULT_ON_GOAL
