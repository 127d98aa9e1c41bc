"""`ClientGoalHandle` and `GoalResult`: a sent goal as the client sees it, until it ends."""

from __future__ import annotations

import asyncio
import concurrent.futures
import threading
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Generic, Protocol

from typing_extensions import TypeVar

from ..errors import GoalRejectedError, ZenrosTimeout
from ..executor import Executor
from ..msgs.builtin_interfaces import Time
from .inbox import Inbox
from .types import GoalStatus

__all__ = ["ClientGoalHandle", "GoalClient", "GoalResult"]

G = TypeVar("G", default=Any)
R = TypeVar("R", default=Any)


class GoalClient(Protocol):
    """What a goal handle needs of its client (`ActionClient`)."""

    name: str

    def refresh_status(self) -> None:
        """Bring the goals' statuses up to date with the server's last status array."""

    def cancel_goal(self, goal_id: uuid.UUID, timeout: float = 5.0) -> list[uuid.UUID]:
        """Ask the server to cancel one goal; the goals now canceling."""

    def forget(self, handle: ClientGoalHandle[Any, Any]) -> None:
        """The goal ended: the client stops following it."""


@dataclass(frozen=True)
class GoalResult(Generic[R]):
    """How a goal ended: its terminal status (SUCCEEDED, CANCELED, ABORTED or, client-side,
    LOST), the result message (a default one when the server sent none), and why (for LOST)."""

    goal_id: uuid.UUID
    status: GoalStatus
    result: R
    reason: str = ""

    @property
    def succeeded(self) -> bool:
        return self.status is GoalStatus.SUCCEEDED


class ClientGoalHandle(Generic[G, R]):
    """A goal sent with `ActionClient.send_goal_async` (of goal type G, result type R).

    ``status`` follows the server (UNKNOWN until the server answers, then ACCEPTED or
    REJECTED, EXECUTING, CANCELING, and a terminal state); ``result()`` blocks until the goal
    ended and returns a `GoalResult`; ``cancel()`` asks the server to cancel it.
    """

    def __init__(self, client: GoalClient, goal_id: uuid.UUID, goal: G,
                 on_feedback: Callable[[Any], None] | None, executor: Executor,
                 inbox: Inbox) -> None:
        self.goal_id = goal_id
        self.goal = goal
        self.stamp = Time()
        self.reason = ""
        self._client = client
        self._executor = executor  # where done callbacks run
        self._inbox = inbox  # the client's feedback queue: the end comes after the feedback
        self._status = GoalStatus.UNKNOWN
        self._accepted: bool | None = None
        self._cond = threading.Condition()
        self._future: concurrent.futures.Future[GoalResult[R]] = concurrent.futures.Future()
        self._on_feedback = on_feedback
        self.key = goal_id.bytes  # the id as the client's table and the wire have it
        self._server_zid = ""
        self._retry_result = False
        self._ended = False

    @property
    def status(self) -> GoalStatus:
        """The goal's state as last reported by the server (or REJECTED/LOST, client-side)."""
        if not self._ended:
            self._client.refresh_status()
        return self._status

    @property
    def accepted(self) -> bool | None:
        """True or False once the server answered the goal; None before."""
        return self._accepted

    @property
    def done(self) -> bool:
        """True once the goal ended (or failed to be sent)."""
        return self._future.done()

    def wait_accepted(self, timeout: float | None = None) -> bool:
        """Block until the server answered: True if it accepted the goal, False if it rejected
        it. Raises `ZenrosTimeout` on timeout, and the send error if the goal never arrived."""
        with self._cond:
            if not self._cond.wait_for(lambda: self._accepted is not None or self._ended,
                                       timeout):
                raise ZenrosTimeout(f"goal {self.goal_id} on {self._client.name}: no answer "
                                    f"within {timeout:g} s")
        if self._accepted is None:
            self._future.result()  # raises the send error
        return bool(self._accepted)

    def result(self, timeout: float | None = None) -> GoalResult[R]:
        """Block until the goal ends and return how.

        Raises:
            GoalRejectedError: the server rejected the goal.
            ActionServerUnavailableError: no server answered the goal.
            ZenrosTimeout: the goal did not end within ``timeout`` seconds (it keeps running).
        """
        try:
            return self._future.result(timeout)
        except concurrent.futures.TimeoutError:
            raise ZenrosTimeout(f"goal {self.goal_id} on {self._client.name} did not end within "
                                f"{timeout:g} s (status {self._status.name})") from None

    async def result_async(self) -> GoalResult[R]:
        """Await the goal's end from any event loop (same errors as `result`)."""
        return await asyncio.wrap_future(self._future)

    def add_done_callback(self, fn: Callable[[ClientGoalHandle[G, R]], None]) -> None:
        """Call ``fn(handle)`` once the goal ended, on the node's event loop thread."""
        executor = self._executor
        self._future.add_done_callback(lambda _f: executor.call_soon(fn, self))

    def cancel(self, timeout: float = 5.0) -> bool:
        """Ask the server to cancel this goal; True if it is now canceling (the goal then ends
        CANCELED, or otherwise if its execute callback decides so)."""
        return self.goal_id in self._client.cancel_goal(self.goal_id, timeout)

    @property
    def server_zid(self) -> str:
        """The session of the server that answered the goal ('' before the answer)."""
        return self._server_zid

    @property
    def wants_feedback(self) -> bool:
        return self._on_feedback is not None

    # ------------------------------------------------------------------ updates (its client's)
    # Called by the goal's `ActionClient` only, as an asyncio Future is set by its owner: the
    # handle keeps the goal's state and changes it itself.

    def advance(self, status: GoalStatus) -> bool:
        """Move forward only: statuses from the topic may arrive late or repeated."""
        with self._cond:
            if self._ended or self._status.terminal or status <= self._status:
                return False
            self._status = status
            self._cond.notify_all()
            return True

    def set_accepted(self, accepted: bool, stamp: Time, reason: str, zid: str) -> bool:
        """Record the server's answer; True if a deferred result request is now due."""
        with self._cond:
            self._accepted = accepted
            self.stamp = stamp
            self._server_zid = zid
            retry, self._retry_result = self._retry_result, False
            self._cond.notify_all()
        if accepted:
            self.advance(GoalStatus.ACCEPTED)
            return retry
        self.set_exception(GoalStatus.REJECTED, GoalRejectedError(
            f"action {self._client.name} rejected goal {self.goal_id}: {reason}"), reason)
        return False

    def defer_result_request(self) -> bool:
        """If the server has not answered the goal yet, mark the result request to be sent
        again once it does (True); False if it already answered."""
        with self._cond:
            if self._accepted is None:
                self._retry_result = True
                return True
            return False

    def _end(self, status: GoalStatus | None, reason: str) -> bool:
        with self._cond:
            if self._ended:
                return False
            self._ended = True
            if status is not None:
                self._status = status
            self.reason = reason
            self._cond.notify_all()
        return True

    def set_result(self, status: GoalStatus, result: R, reason: str = "") -> None:
        """The goal ended with ``status`` (terminal) and ``result``."""
        def finish() -> None:
            if self._end(status, reason):
                self._future.set_result(GoalResult(self.goal_id, status, result, reason))
                self._client.forget(self)

        self._in_order(finish)

    def set_exception(self, status: GoalStatus | None, exc: Exception, reason: str = "") -> None:
        """The goal failed (rejected, never answered, client closed): `result` raises ``exc``."""
        def fail() -> None:
            if self._end(status, reason or str(exc)):
                self._future.set_exception(exc)
                self._client.forget(self)

        self._in_order(fail)

    def _in_order(self, fn: Callable[[], None]) -> None:
        """End the goal now, or (with a feedback callback) after the feedback received so far."""
        if self._on_feedback is None:
            fn()
        else:
            self._inbox.put(fn)

    def deliver_feedback(self, msg: Any) -> None:
        """Hand one feedback message to the callback (on the client's inbox thread)."""
        if not self._ended and self._on_feedback is not None:
            self._on_feedback(msg)

    def __repr__(self) -> str:
        return f"<ClientGoalHandle {self.goal_id} {self._status.name}>"
