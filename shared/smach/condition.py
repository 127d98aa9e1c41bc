"""`ConditionState`: check a predicate on userdata, optionally several times, at a poll interval."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from ..errors import InvalidStateError
from .state import State
from .userdata import UserDataAccess

__all__ = ["ConditionState"]


class ConditionState(State):
    """Outcome ``"true"`` once ``cond_cb`` holds ``max_checks`` times in a row, else ``"false"``.

    As smach_ros's ConditionState: the first False ends the state with ``"false"``, and so
    does running out of ``timeout``; after each True check short of ``max_checks`` it may be
    preempted (outcome ``"preempted"``), else it waits ``poll_interval`` seconds. The
    condition is always checked once before a preempt is honoured. ``max_checks=-1`` checks until the
    condition fails, the timeout passes or a preempt arrives: a "while true" monitor.

    The waiting is injectable so tests never sleep: ``wait(seconds)`` defaults to waiting
    on the preempt flag (so a preempt cuts the wait short) and ``now()`` to
    `time.monotonic`. Neither needs a ROS or Zenoh clock.

    Args:
        cond_cb: Predicate on the userdata view.
        input_keys: Keys the predicate reads.
        poll_interval: Seconds between checks.
        timeout: Give up (outcome ``"false"``) after this many seconds; None: never.
        max_checks: Consecutive True checks needed; -1: check for ever.
        wait: Called with ``poll_interval`` between checks.
        now: Monotonic seconds, for the timeout.
    """

    def __init__(
        self,
        cond_cb: Callable[[UserDataAccess], bool],
        input_keys: Sequence[str] = (),
        poll_interval: float = 0.05,
        timeout: float | None = None,
        max_checks: int = 1,
        wait: Callable[[float], object] | None = None,
        now: Callable[[], float] = time.monotonic,
    ) -> None:
        super().__init__(outcomes=("true", "false", "preempted"), input_keys=input_keys)
        if not callable(cond_cb):
            raise InvalidStateError(f"cond_cb must be callable, got {type(cond_cb).__name__}")
        if max_checks == 0 or max_checks < -1:
            raise InvalidStateError(f"max_checks must be >= 1, or -1 for ever; got {max_checks}")
        if poll_interval < 0 or (timeout is not None and timeout < 0):
            raise InvalidStateError(
                f"poll_interval and timeout must be >= 0, got {poll_interval} and {timeout}"
            )
        self._cond = cond_cb
        self._interval = poll_interval
        self._timeout = timeout
        self._max_checks = max_checks
        self._wait = wait if wait is not None else self.wait_for_preempt
        self._now = now
        self.checks = 0
        """How many times the condition held in the last run."""

    def execute(self, userdata: UserDataAccess) -> str:
        """Poll the condition; see the class docstring for the outcomes."""
        start = self._now()
        self.checks = 0
        while True:
            if self._timeout is not None and self._now() - start > self._timeout:
                return "false"
            if not self._cond(userdata):
                return "false"
            self.checks += 1
            if self._max_checks != -1 and self.checks >= self._max_checks:
                return "true"
            if self.preempt_requested():
                self.service_preempt()
                return "preempted"
            self._wait(self._interval)
