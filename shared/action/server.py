"""`ActionServer`: serves one action (goal, cancel and result queryables; feedback and status
topics) and runs accepted goals under a scheduling policy."""

from __future__ import annotations

import asyncio
import inspect
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import zenoh

from ..codec import codec_for
from ..errors import EncodeError, GoalRejectedError, GoalStateError
from ..message import ActionType
from .goal_handle import ServerGoalHandle
from .goals import GoalTable
from .policies import GoalPolicy, Plan, Scheduler
from .states import GoalEvent, transition
from .transport import answer, answer_err, decode_query, encoding_for, status_publisher
from .types import (
    ZERO_UUID,
    CancelCode,
    CancelGoalRequest,
    CancelGoalResponse,
    CancelResponse,
    GoalResponse,
    GoalStatus,
    GoalStatusArray,
    GoalStatusMsg,
    uuid_from_msg,
)
from .wire import wire_types
from .workers import WorkerPool

if TYPE_CHECKING:
    from ..node import Node

__all__ = ["ActionServer"]

Handle = ServerGoalHandle[Any]
_FAILED = object()
STATUS_DELAY = 0.002  # seconds: state changes within this window share one status array


class ActionServer:
    """Serves ``name`` with ``action_type``.

    Args:
        node: the node that owns the server (closing the node closes it).
        action_type: e.g. ``example_interfaces.Fibonacci``.
        name: the action name, resolved like a topic name.
        execute_callback: ``execute(goal_handle) -> Result``, plain (run on a worker thread) or
            ``async def`` (run on the node's event loop). It ends the goal with
            ``goal_handle.succeed()``, ``abort()`` or ``canceled()``; if it returns without one,
            the goal ends CANCELED when a cancel was requested and ABORTED otherwise (rclpy
            aborts), with a warning.
        goal_callback: ``goal_callback(goal) -> GoalResponse | bool``, run on the receiving
            thread; raise `GoalRejectedError` to reject with a reason. Default: accept.
        cancel_callback: ``cancel_callback(goal_handle) -> CancelResponse | bool``. Default:
            accept (rclpy's default rejects).
        policy: a `GoalPolicy` or its name (``simple``, ``queue``, ``reject_if_busy``,
            ``parallel``, ``parallel:<n>``, ``queue:<max_waiting>``).
        result_timeout: seconds a result stays available after its goal ended (ROS 2: 900).
        status_history: how many ended goals the status array keeps listing.
        shutdown_timeout: seconds `close` waits for running goals after canceling them.
    """

    def __init__(
        self,
        node: Node,
        action_type: ActionType,
        name: str,
        execute_callback: Callable[[Handle], Any],
        goal_callback: Callable[[Any], GoalResponse | bool] | None = None,
        cancel_callback: Callable[[Handle], CancelResponse | bool] | None = None,
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
        self._execute = execute_callback
        self._is_async = inspect.iscoroutinefunction(execute_callback)
        self._goal_cb = goal_callback
        self._cancel_cb = cancel_callback
        self._wire = wire = wire_types(action_type)
        self._sg_req = codec_for(wire.SendGoalRequest)
        self._sg_res = codec_for(wire.SendGoalResponse)
        self._gr_req = codec_for(wire.GetResultRequest)
        self._gr_res = codec_for(wire.GetResultResponse)
        self._fb = codec_for(wire.FeedbackMessage)
        self._cg_req = codec_for(CancelGoalRequest)
        self._cg_res = codec_for(CancelGoalResponse)
        self._status_codec = codec_for(GoalStatusArray)
        self._enc = {t: encoding_for(t) for t in (wire.SendGoalResponse, wire.GetResultResponse,
                                                  CancelGoalResponse)}
        self._lock = threading.RLock()
        self._idle = threading.Condition(self._lock)
        self._table = GoalTable(result_timeout, status_history)
        self._sched: Scheduler[bytes] = Scheduler(self.policy)
        self._workers = WorkerPool(f"action{self.name}", self.logger)
        self._timer: asyncio.TimerHandle | None = None
        self._purge_armed = False
        self._status_dirty = self._flush_pending = False
        self._closing = False
        self.closed = False
        s, key = ctx.session, self._key
        self._fb_pub: Any = s.declare_publisher(key("feedback"), encoding=encoding_for(wire.FeedbackMessage),
                                           congestion_control=zenoh.CongestionControl.BLOCK)
        self._status_pub: Any = status_publisher(s, key("status"), GoalStatusArray)
        # One queryable for the three request keys (send_goal, cancel_goal, get_result): its
        # callbacks run on one thread in arrival order, so a client may send get_result right
        # behind send_goal. (A plain callback: Zenoh calls it on a thread of its own, keeping
        # Python work and the GIL off Zenoh's network threads.)
        self._handlers = {"send_goal": self._on_send_goal, "cancel_goal": self._on_cancel,
                          "get_result": self._on_get_result}
        self._queryable: Any = s.declare_queryable(key("*"), self._on_query, complete=True)
        with self._lock:
            self._publish_status()
        self._token: Any = s.liveliness().declare_token(ctx.keys.entity_token(
            "act", node.fqn, self.name, action_type.name, "", ctx.zid, ctx.next_eid()))
        node._track(self)

    def _key(self, part: str) -> str:
        return self._ctx.keys.action(self.name, part)

    def _on_query(self, query: zenoh.Query) -> None:
        part = str(query.key_expr).rsplit("/", 1)[-1]
        handler = self._handlers.get(part)
        if handler is not None:
            handler(query)
            return
        with query:
            self._reply_err(query, "BadRequest", (
                f"action {self.name}: no request {part!r}; valid: {', '.join(self._handlers)}"))

    # ------------------------------------------------------------------ send_goal

    def _on_send_goal(self, query: zenoh.Query) -> None:
        with query:
            req = decode_query(query, self._sg_req, f"action {self.name} send_goal")
            if isinstance(req, str):
                return self._reply_err(query, "BadRequest", req)
            gid = uuid_from_msg(req.goal_id)
            if gid == ZERO_UUID:
                return self._reply_err(query, "BadRequest", f"action {self.name} send_goal: "
                                       "goal_id must be a non-zero UUID")
            handle: Handle = ServerGoalHandle(self, gid, req.goal)
            with self._lock:
                fresh = not self._closing and self._table.add_pending(handle)
            if not fresh:
                why = "server is shutting down" if self._closing else f"duplicate goal id {gid}"
                return self._respond(query, False, why)
            reason = self._ask_goal_callback(req.goal)
            launch: list[Handle] = []
            with self._lock:
                if not reason and self._closing:
                    reason = "server is shutting down"
                if not reason:
                    plan = self._sched.offer(handle._key)
                    reason = plan.reject
                if reason:
                    self._table.remove(handle)
                    for w in handle._waiters:
                        self._reply_err(w, "GoalRejected", reason)
                    handle._waiters.clear()
                    self._respond(query, False, reason)
                    return
                handle.stamp = handle._info.stamp = self._node.now()
                handle._status = GoalStatus.ACCEPTED
                self._table.activate(handle)
                launch = self._apply(plan)
                self._respond(query, True, "", handle)  # answer first, then run the goal
                self._launch(launch)
                self._publish_status()

    def _ask_goal_callback(self, goal: Any) -> str:
        """'' to accept, else the rejection reason."""
        if self._goal_cb is None:
            return ""
        try:
            answer = self._goal_cb(goal)
        except GoalRejectedError as exc:
            return str(exc) or "rejected by the goal callback"
        except Exception as exc:
            self.logger.exception("action %s: goal callback raised", self.name)
            return f"goal callback raised {type(exc).__name__}: {exc}"
        if answer is GoalResponse.ACCEPT or answer is True:
            return ""
        return "rejected by the goal callback"

    def _respond(self, query: zenoh.Query, accepted: bool, reason: str,
                 handle: Handle | None = None) -> None:
        res = self._wire.SendGoalResponse(accepted=accepted, reason=reason)
        if accepted and handle is not None:
            res.stamp = handle.stamp
        answer(query, self._sg_res.encode(res), self._enc[self._wire.SendGoalResponse])

    # ------------------------------------------------------------------ scheduling, execution

    def _apply(self, plan: Plan[bytes]) -> list[Handle]:
        """Carry out a scheduler plan (under the lock); return the goals to launch."""
        active = self._table.active
        for key in plan.preempt:
            self._request_cancel(active[key])
        for key in plan.drop:
            h = active[key]
            h._status = transition(transition(h._status, GoalEvent.CANCEL_GOAL), GoalEvent.CANCELED)
            self._retire(h, self.action_type.Result())
        launch = []
        for key in plan.start:
            h = active[key]
            h._status = transition(h._status, GoalEvent.EXECUTE, str(h.goal_id))
            launch.append(h)
        return launch

    def _launch(self, handles: list[Handle]) -> None:
        for h in handles:
            if self._is_async:
                self._ctx.executor.submit(self._run_async(h))
            else:
                self._workers.submit(lambda h=h: self._complete(h, self._run_sync(h)))  # type: ignore[misc]

    def _run_sync(self, h: Handle) -> Any:
        try:
            return self._execute(h)
        except Exception:
            self.logger.exception("action %s: execute callback raised for goal %s", self.name,
                                  h.goal_id)
            return _FAILED

    async def _run_async(self, h: Handle) -> None:
        try:
            result = await self._execute(h)
        except asyncio.CancelledError:
            self._complete(h, _FAILED)
            raise
        except Exception:
            self.logger.exception("action %s: execute callback raised for goal %s", self.name,
                                  h.goal_id)
            result = _FAILED
        self._complete(h, result)

    def _complete(self, h: Handle, result: Any) -> None:
        """The execute callback returned (or raised): settle state and result, start the next."""
        result_type = self.action_type.Result
        with self._lock:
            if h._result is not None:  # already ended by close()
                return
            changed = h._status.active
            if changed:
                event = GoalEvent.CANCELED if h._status is GoalStatus.CANCELING else GoalEvent.ABORT
                if result is not _FAILED:
                    self.logger.warning(
                        "action %s: execute returned without succeed(), abort() or canceled() "
                        "for goal %s; marking it %s", self.name, h.goal_id, event.value.upper())
                h._status = transition(h._status, event)
            if result is None or result is _FAILED:
                result = result_type()
            elif type(result) is not result_type:
                self.logger.error("action %s: execute returned %s, expected %s; sending a "
                                  "default result", self.name, type(result).__name__,
                                  result_type.__name__)
                result = result_type()
            self._retire(h, result)
            launch = self._apply(self._sched.finish(h._key))
            if changed or launch:
                self._publish_status()
            self._idle.notify_all()
        self._launch(launch)

    def _retire(self, h: Handle, result: Any) -> None:
        """Record the result (under the lock), answer waiting result requests, start expiry."""
        h._result = result
        self._table.retire(h, time.monotonic())
        if h._waiters:
            data = self._result_payload(h)
            for w in h._waiters:
                answer(w, data, self._enc[self._wire.GetResultResponse])
            h._waiters.clear()
        self._arm_expiry()

    def _result_payload(self, h: Handle) -> bytes:
        res = self._wire.GetResultResponse(status=int(h._status), result=h._result)
        return self._gr_res.encode(res)

    # ------------------------------------------------------------------ goal handle calls

    def _end(self, h: Handle, event: GoalEvent) -> None:
        with self._lock:
            h._status = transition(h._status, event, str(h.goal_id))
            self._publish_status()

    def _publish_feedback(self, h: Handle, feedback: Any) -> None:
        if type(feedback) is not self.action_type.Feedback:
            raise EncodeError(f"action {self.name} feedback is "
                              f"{codec_for(self.action_type.Feedback).type_name}, "
                              f"got {type(feedback).__name__}")
        if not h._status.active:
            raise GoalStateError(f"cannot publish feedback for goal {h.goal_id}: it is "
                                 f"{h._status.name}")
        if self.closed:
            return
        msg = self._wire.FeedbackMessage(goal_id=h._info.goal_id, feedback=feedback)
        self._fb_pub.put(self._fb.encode(msg))

    def _request_cancel(self, h: Handle) -> None:
        if h._status in (GoalStatus.ACCEPTED, GoalStatus.EXECUTING):
            h._status = transition(h._status, GoalEvent.CANCEL_GOAL)
            h._cancel.set()

    # ------------------------------------------------------------------ cancel_goal

    def _on_cancel(self, query: zenoh.Query) -> None:
        with query:
            req = decode_query(query, self._cg_req, f"action {self.name} cancel_goal")
            if isinstance(req, str):
                return self._reply_err(query, "BadRequest", req)
            gid = uuid_from_msg(req.goal_info.goal_id)
            key = None if gid == ZERO_UUID else gid.bytes
            stamp = req.goal_info.stamp
            stamp_ns = stamp.sec * 1_000_000_000 + stamp.nanosec
            with self._lock:
                targets = list(self._table.cancel_targets(key, stamp_ns))
                state = self._table.terminal_or_unknown(key) if key else GoalStatus.UNKNOWN
            if key is not None and stamp_ns == 0 and not targets:
                code = (CancelCode.ERROR_UNKNOWN_GOAL_ID if state is GoalStatus.UNKNOWN
                        else CancelCode.ERROR_GOAL_TERMINATED)
                return self._reply_cancel(query, code, [])
            accepted = [h for h in targets
                        if h._status is GoalStatus.CANCELING or self._ask_cancel_callback(h)]
            with self._lock:
                for h in accepted:
                    self._request_cancel(h)
                    if self._sched.withdraw(h._key):  # waiting, never ran: ends here
                        h._status = transition(h._status, GoalEvent.CANCELED)
                        self._retire(h, self.action_type.Result())
                if accepted:
                    self._publish_status()
            code = CancelCode.ERROR_REJECTED if targets and not accepted else CancelCode.ERROR_NONE
            self._reply_cancel(query, code, accepted)

    def _ask_cancel_callback(self, h: Handle) -> bool:
        if self._cancel_cb is None:
            return True
        try:
            answer = self._cancel_cb(h)
        except Exception:
            self.logger.exception("action %s: cancel callback raised; rejecting", self.name)
            return False
        return answer is CancelResponse.ACCEPT or answer is True

    def _reply_cancel(self, query: zenoh.Query, code: CancelCode, goals: list[Handle]) -> None:
        res = CancelGoalResponse(return_code=int(code),
                                 goals_canceling=[h._info for h in goals])
        answer(query, self._cg_res.encode(res), self._enc[CancelGoalResponse])

    # ------------------------------------------------------------------ get_result

    def _on_get_result(self, query: zenoh.Query) -> None:
        req = decode_query(query, self._gr_req, f"action {self.name} get_result")
        if isinstance(req, str):
            with query:
                return self._reply_err(query, "BadRequest", req)
        gid = uuid_from_msg(req.goal_id)
        with self._lock:
            self._table.expire(time.monotonic())
            h = self._table.lookup(gid.bytes)
            if h is not None and h._result is None:
                h._waiters.append(query)  # answered when the goal's result is set
                return
            data = None if h is None else self._result_payload(h)
        with query:
            if data is not None:
                answer(query, data, self._enc[self._wire.GetResultResponse])
                return
            self._reply_err(query, "UnknownGoal", (
                f"action {self.name}: unknown goal id {gid}: it was never accepted by this server, "
                f"or its result expired (results are kept {self._table.result_timeout:g} s)"))

    # ------------------------------------------------------------------ status, expiry

    def _publish_status(self) -> None:
        """Note a state change (under the lock); the executor publishes the status array soon
        after. Changes made meanwhile coalesce into that one array, which keeps publishing off
        the threads that answer queries and run goals."""
        self._status_dirty = True
        if not self._flush_pending and not self.closed:
            self._flush_pending = True
            self._ctx.executor.call_soon(self._ctx.executor.loop.call_later, STATUS_DELAY,
                                         self._flush_status)

    def _flush_status(self) -> None:
        """Publish the full status array if it changed since the last one."""
        with self._lock:
            self._flush_pending = False
            if not self._status_dirty or self.closed:
                return
            self._status_dirty = False
            arr = GoalStatusArray(status_list=[
                GoalStatusMsg(goal_info=h._info, status=int(h._status))
                for h in self._table.status_list()])
            self._status_pub.put(self._status_codec.encode(arr))

    def _arm_expiry(self) -> None:
        if not self._purge_armed and not self.closed:
            self._purge_armed = True
            self._ctx.executor.call_soon(self._schedule_purge)

    def _schedule_purge(self) -> None:
        with self._lock:
            due = self._table.next_expiry()
            if due is None or self.closed:
                self._timer, self._purge_armed = None, False
                return
            loop = self._ctx.executor.loop
            self._timer = loop.call_later(max(0.0, due - time.monotonic()), self._purge)

    def _purge(self) -> None:
        with self._lock:
            if self._table.expire(time.monotonic()):
                self._publish_status()
        self._schedule_purge()

    def _reply_err(self, query: zenoh.Query, kind: str, message: str) -> None:
        if kind == "BadRequest":
            self.logger.warning("%s", message)
        answer_err(query, kind, message)

    # ------------------------------------------------------------------ lifecycle

    def close(self) -> None:
        """Stop taking goals, cancel the running ones, wait ``shutdown_timeout`` for them, abort
        what is left (answering every pending result request), then undeclare everything."""
        with self._lock:
            if self._closing:
                return
            self._closing = True
        with self._lock:
            for key in list(self._sched.waiting):
                self._sched.withdraw(key)
                h = self._table.active[key]
                h._status = transition(h._status, GoalEvent.ABORT)
                self._retire(h, self.action_type.Result())
            for h in list(self._table.active.values()):
                self._request_cancel(h)
            self._status_dirty = True
            self._flush_status()
            self._idle.wait_for(lambda: not self._table.active, self.shutdown_timeout)
            for h in list(self._table.active.values()):
                if h._status.active:
                    h._status = transition(h._status, GoalEvent.ABORT)
                self.logger.warning("action %s: goal %s still running at shutdown; aborted",
                                    self.name, h.goal_id)
                self._retire(h, self.action_type.Result())
            self._status_dirty = True
            self._flush_status()
            self.closed = True
            if self._timer is not None:
                self._ctx.executor.call_soon(self._timer.cancel)
        self._token.undeclare()
        self._queryable.undeclare()
        self._fb_pub.undeclare()
        self._status_pub.undeclare()
        self._workers.close()

    def __repr__(self) -> str:
        return f"<ActionServer {self.name} [{self.action_type.name}] policy={self.policy}>"
