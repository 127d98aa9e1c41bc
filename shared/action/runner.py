"""`GoalRunner`: an action server's accepted goals, from scheduling and execution to the expiry
of their results."""

from __future__ import annotations

import asyncio
import logging
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol

from ..executor import Executor
from ..message import ActionType
from .goal_handle import ServerGoalHandle
from .goals import GoalTable
from .policies import GoalPolicy, Plan, Scheduler
from .states import GoalEvent
from .types import GoalStatus
from .workers import WorkerPool

if TYPE_CHECKING:
    import zenoh

__all__ = ["GoalRunner"]

Handle = ServerGoalHandle[Any]
_FAILED = object()


class StatusSink(Protocol):
    """Where state changes are reported (the server's `StatusPublisher`)."""

    def mark(self) -> None: ...

    def flush(self, force: bool = False) -> None: ...


class GoalRunner:
    """Runs goals under a `GoalPolicy`: plain execute callbacks on worker threads, ``async
    def`` ones on the executor; settles states and results; keeps results ``result_timeout``
    seconds. Every method marked "locked" expects the caller to hold ``lock``.

    Args:
        deliver: answers the result requests that waited on a goal once its result is set.
    """

    def __init__(self, name: str, action_type: ActionType, execute: Callable[[Handle], Any],
                 is_async: bool, policy: GoalPolicy, table: GoalTable, status: StatusSink,
                 lock: threading.RLock, executor: Executor, logger: logging.Logger,
                 deliver: Callable[[Handle, list[zenoh.Query]], None]) -> None:
        self.name = name
        self.lock = lock
        self.table = table
        self.sched: Scheduler[bytes] = Scheduler(policy)
        self._result_type = action_type.Result
        self._execute = execute
        self._is_async = is_async
        self._status = status
        self._executor = executor
        self._logger = logger
        self._deliver = deliver
        self._idle = threading.Condition(lock)
        self._workers = WorkerPool(f"action{name}", logger)
        self._timer: asyncio.TimerHandle | None = None
        self._purge_armed = False
        self.closed = False

    @property
    def on_workers(self) -> bool:
        """True if goals run on threads (a plain execute callback), False on the event loop."""
        return not self._is_async

    # ------------------------------------------------------------------ admission (locked)

    def accept(self, h: Handle, plan: Plan[bytes]) -> list[Handle]:
        """Locked: make an offered goal ACCEPTED and carry out the plan; return the goals to
        `launch` (after the client got its answer)."""
        h.transition(GoalEvent.ACCEPT)
        self.table.activate(h)
        return self._apply(plan)

    def _apply(self, plan: Plan[bytes]) -> list[Handle]:
        if not (plan.preempt or plan.drop or plan.start):
            return []
        active = self.table.active
        launch = []
        for key in plan.preempt:
            h = active.get(key)
            if h is None:  # it ended without leaving the scheduler: what may run now, runs
                self._logger.warning("action %s: goal %s had ended but was still scheduled as "
                                     "running; dropped from the schedule", self.name, key.hex())
                launch += self._apply(self.sched.finish(key))
                continue
            self.request_cancel(h)
        for key in plan.drop:
            h = active[key]
            h.transition(GoalEvent.CANCEL_GOAL)
            h.transition(GoalEvent.CANCELED)
            self._retire(h, self._result_type())
        for key in plan.start:
            h = active[key]
            h.transition(GoalEvent.EXECUTE)
            launch.append(h)
        return launch

    def request_cancel(self, h: Handle) -> None:
        """Locked: ask a goal to cancel (a client's request, a preemption or shutdown); a goal
        that was only waiting ends CANCELED at once."""
        if h.status in (GoalStatus.ACCEPTED, GoalStatus.EXECUTING):
            h.transition(GoalEvent.CANCEL_GOAL)
        if self.sched.withdraw(h.key):
            h.transition(GoalEvent.CANCELED)
            self._retire(h, self._result_type())

    # ------------------------------------------------------------------ execution

    def launch(self, handles: list[Handle]) -> None:
        for h in handles:
            if self._is_async:
                self._executor.submit(self._run_async(h))
            else:
                self._workers.submit(lambda h=h: self.run(h))  # type: ignore[misc]

    def run(self, h: Handle) -> None:
        """Run a launched goal with a plain execute callback on the calling thread."""
        self._complete(h, self._run_sync(h))

    def _run_sync(self, h: Handle) -> Any:
        try:
            return self._execute(h)
        except Exception:
            self._logger.exception("action %s: execute callback raised for goal %s", self.name,
                                   h.goal_id)
            return _FAILED

    async def _run_async(self, h: Handle) -> None:
        try:
            result = await self._execute(h)
        except asyncio.CancelledError:
            self._complete(h, _FAILED)
            raise
        except Exception:
            self._logger.exception("action %s: execute callback raised for goal %s", self.name,
                                   h.goal_id)
            result = _FAILED
        self._complete(h, result)

    def _complete(self, h: Handle, result: Any) -> None:
        """The execute callback returned (or raised): settle state and result, start the next."""
        with self.lock:
            if h.has_result:  # already ended by shutdown
                return
            if h.is_active:
                event = GoalEvent.CANCELED if h.status is GoalStatus.CANCELING else GoalEvent.ABORT
                if result is not _FAILED:
                    self._logger.warning(
                        "action %s: execute returned without succeed(), abort() or canceled() "
                        "for goal %s; marking it %s", self.name, h.goal_id, event.value.upper())
                h.transition(event)
            if result is None or result is _FAILED:
                result = self._result_type()
            elif type(result) is not self._result_type:
                self._logger.error("action %s: execute returned %s, expected %s; sending a "
                                   "default result", self.name, type(result).__name__,
                                   self._result_type.__name__)
                result = self._result_type()
            try:
                self._retire(h, result)
            finally:  # whatever answering its requests raised, the next goal starts
                launch = self._apply(self.sched.finish(h.key))
                self._idle.notify_all()
        self.launch(launch)

    def _retire(self, h: Handle, result: Any) -> None:
        """Locked: record the result, answer waiting result requests, start expiry."""
        waiters = h.set_result(result)
        self.table.retire(h, time.monotonic())
        if waiters:
            self._deliver(h, waiters)
        if not self._purge_armed and not self.closed:
            self._purge_armed = True
            self._executor.call_soon(self._schedule_purge)

    # ------------------------------------------------------------------ expiry

    def _schedule_purge(self) -> None:
        with self.lock:
            due = self.table.next_expiry()
            if due is None or self.closed:
                self._timer, self._purge_armed = None, False
                return
            loop = self._executor.loop
            self._timer = loop.call_later(max(0.0, due - time.monotonic()), self._purge)

    def _purge(self) -> None:
        with self.lock:
            if self.table.expire(time.monotonic()):
                self._status.mark()
        self._schedule_purge()

    # ------------------------------------------------------------------ shutdown

    def shutdown(self, timeout: float) -> None:
        """Abort waiting goals, cancel running ones, wait ``timeout`` s for them, abort the rest."""
        with self.lock:
            for key in list(self.sched.waiting):
                self.sched.withdraw(key)
                h = self.table.active[key]
                h.transition(GoalEvent.ABORT)
                self._retire(h, self._result_type())
            for h in list(self.table.active.values()):
                self.request_cancel(h)
            self._status.flush(force=True)
            self._idle.wait_for(lambda: not self.table.active, timeout)
            for h in list(self.table.active.values()):
                if h.is_active:
                    h.transition(GoalEvent.ABORT)
                self._logger.warning("action %s: goal %s still running at shutdown; aborted",
                                     self.name, h.goal_id)
                self._retire(h, self._result_type())
            self._status.flush(force=True)
            self.closed = True
            if self._timer is not None:
                self._executor.call_soon(self._timer.cancel)
        self._workers.close()
