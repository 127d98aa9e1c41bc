"""`ServerGoalHandle`: one goal as its execute callback sees it (feedback, end states, cancel)."""

from __future__ import annotations

import threading
import uuid
from typing import TYPE_CHECKING, Any, Generic, Protocol

from typing_extensions import TypeVar

from ..errors import GoalStateError
from ..msgs.builtin_interfaces import Time
from .states import GoalEvent, transition
from .types import UUID, GoalInfo, GoalStatus, uuid_msg

if TYPE_CHECKING:
    import zenoh

__all__ = ["GoalHost", "ServerGoalHandle"]

G = TypeVar("G")
F = TypeVar("F", default=Any)


class GoalHost(Protocol):
    """What a goal handle needs of its server (`ActionServer`)."""

    lock: threading.RLock
    """Guards the server's goals; a handle changes its state under it."""

    def goal_changed(self) -> None:
        """A goal's state changed (called under ``lock``): the status array is due."""

    def encode_feedback(self, handle: ServerGoalHandle[Any, Any], feedback: Any) -> bytes:
        """Check ``feedback``'s type and encode it for ``handle``'s goal."""

    def put_feedback(self, handle: ServerGoalHandle[Any, Any], data: bytes) -> None:
        """Send encoded feedback of an active goal (called under ``lock``)."""


class ServerGoalHandle(Generic[G, F]):
    """A goal on the server (of goal type G, feedback type F; ``ServerGoalHandle[Goal]``
    leaves F open). The execute callback reads ``request``, calls `publish_feedback`,
    polls `is_cancel_requested` (or blocks in `wait_for_cancel`), ends the goal with
    `succeed`, `abort` or `canceled`, and returns the result message.

    Attributes:
        request: the goal message.
        stamp: when the server accepted the goal (its node clock).
    """

    def __init__(self, server: GoalHost, goal_id: uuid.UUID | bytes, request: G,
                 goal_id_msg: UUID | None = None) -> None:
        # The id as 16 bytes (the server's key); the UUID object is made when first read.
        self.key = goal_id.bytes if isinstance(goal_id, uuid.UUID) else bytes(goal_id)
        self._goal_id = goal_id if isinstance(goal_id, uuid.UUID) else None
        self.request = request
        self.stamp = Time()
        self._server = server
        # The state, changed only by `transition`, under the server's lock (one lock for the
        # server's table and all its goals: no order between two locks to keep).
        self._lock: threading.RLock = server.lock if server is not None else threading.RLock()
        self._status = GoalStatus.UNKNOWN
        self._cancel_requested = False
        self._cancel_event: threading.Event | None = None  # made for wait_for_cancel only
        # The server's bookkeeping, changed through the methods below under the server's lock:
        # the wire id as received (when the server has it), stamped on acceptance; the result
        # once set; the requests waiting for it; a send_goal query still owed its acceptance.
        self._info = GoalInfo(goal_id=goal_id_msg or uuid_msg(self.goal_id))
        self._result: Any = None
        self._waiters: list[zenoh.Query] = []
        self._owed: zenoh.Query | None = None

    @property
    def goal_id(self) -> uuid.UUID:
        """The client-chosen UUID."""
        gid = self._goal_id
        if gid is None:
            gid = self._goal_id = uuid.UUID(bytes=self.key)
        return gid

    def __str__(self) -> str:
        return str(self.goal_id)

    @property
    def goal(self) -> G:
        """The goal message (rclpy calls it ``request``; both work)."""
        return self.request

    @property
    def status(self) -> GoalStatus:
        return self._status

    @property
    def is_active(self) -> bool:
        """True until the goal reaches a terminal state."""
        return self._status.active

    @property
    def is_executing(self) -> bool:
        return self._status is GoalStatus.EXECUTING

    @property
    def is_cancel_requested(self) -> bool:
        """True once a client canceled the goal or a newer goal preempted it."""
        return self._cancel_requested

    def wait_for_cancel(self, timeout: float | None = None) -> bool:
        """Block until a cancel is requested (True) or ``timeout`` passes (False): an
        interruptible sleep for blocking execute callbacks."""
        event = self._cancel_event
        if event is None:
            with self._lock:  # the lock `transition` sets the flag under
                event = self._cancel_event
                if event is None:
                    event = self._cancel_event = threading.Event()
                    if self._cancel_requested:
                        event.set()
        return event.wait(timeout)

    def transition(self, event: GoalEvent) -> GoalStatus:
        """Move the goal by ``event`` (the one way its state changes; the server's goal
        table, scheduler and this handle's end methods all go through it) and tell the
        server; returns the new state. A cancel request (`GoalEvent.CANCEL_GOAL`) also
        raises `is_cancel_requested` and wakes `wait_for_cancel`.

        Raises:
            GoalStateError: ``event`` is not valid in the current state (names the valid ones).
        """
        with self._lock:
            self._status = status = transition(self._status, event, self)
            if event is GoalEvent.CANCEL_GOAL:
                self._cancel_requested = True
                if self._cancel_event is not None:
                    self._cancel_event.set()
            if self._server is not None:
                self._server.goal_changed()
            return status

    def publish_feedback(self, feedback: F) -> None:
        """Send feedback for this goal; raises `EncodeError` for another type than the
        action's Feedback and `GoalStateError` once the goal has ended."""
        data = self._server.encode_feedback(self, feedback)
        with self._lock:
            if not self._status.active:
                raise GoalStateError(f"cannot publish feedback for goal {self.goal_id}: it is "
                                     f"{self._status.name}")
            self._server.put_feedback(self, data)

    def succeed(self) -> None:
        """End the goal as SUCCEEDED (from EXECUTING or CANCELING)."""
        self.transition(GoalEvent.SUCCEED)

    def abort(self) -> None:
        """End the goal as ABORTED (from EXECUTING or CANCELING)."""
        self.transition(GoalEvent.ABORT)

    def canceled(self) -> None:
        """End the goal as CANCELED (only after a cancel request: from CANCELING)."""
        self.transition(GoalEvent.CANCELED)

    # ------------------------------------------------------------------ the server's bookkeeping
    # Called by the server under its lock (as asyncio's Future is set by its owner): the
    # handle keeps the state, the server decides when it changes.

    @property
    def info(self) -> GoalInfo:
        """The goal's id and acceptance stamp, as the status array and cancel replies list it."""
        return self._info

    def accept_at(self, stamp: Time) -> None:
        """The server accepted the goal at ``stamp``."""
        self.stamp = self._info.stamp = stamp

    @property
    def has_result(self) -> bool:
        return self._result is not None

    @property
    def result(self) -> Any:
        """The result message once set (None before)."""
        return self._result

    def set_result(self, result: Any) -> list[zenoh.Query]:
        """Record the result; returns the requests that waited for it (now the server's to
        answer) and forgets them."""
        self._result = result
        waiters, self._waiters = self._waiters, []
        return waiters

    def add_waiter(self, query: zenoh.Query) -> None:
        """A request to answer with the result once it is set."""
        self._waiters.append(query)

    def take_waiters(self) -> list[zenoh.Query]:
        """The requests waiting for the result (a goal that will have none: rejected)."""
        waiters, self._waiters = self._waiters, []
        return waiters

    def owe_acceptance(self, query: zenoh.Query) -> None:
        """Hold back the acceptance of the goal on ``query`` (it rides on the result reply
        if the goal ends soon); the query also waits for the result."""
        self._owed = query
        self._waiters.append(query)

    @property
    def owes_acceptance(self) -> bool:
        """Whether a send_goal query still waits for its acceptance (read without the lock:
        a hint; `take_owed` under the lock decides)."""
        return self._owed is not None

    def take_owed(self) -> zenoh.Query | None:
        """The send_goal query still owed its acceptance, if any (it is owed no longer)."""
        owed, self._owed = self._owed, None
        return owed

    def __repr__(self) -> str:
        return f"<ServerGoalHandle {self.goal_id} {self._status.name}>"
