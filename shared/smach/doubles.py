"""Test doubles: small states with scripted outcomes, for tests of anything built on smach."""

from __future__ import annotations

import threading
from collections.abc import Sequence

from ..errors import InvalidStateError
from .state import State, names
from .userdata import UserDataAccess
from .wiring import listing

__all__ = [
    "FailState",
    "FixedOutcome",
    "OutcomeQueue",
    "RaiseState",
    "SucceedState",
    "WaitForPreempt",
]


class FixedOutcome(State):
    """Returns the same outcome every time; counts its runs in `executions`.

    Args:
        outcome: What `execute` returns.
        outcomes: The declared outcomes (default: just ``outcome``); ``outcome`` is added.
    """

    def __init__(self, outcome: str, outcomes: Sequence[str] = ()) -> None:
        super().__init__((*names(outcomes, "outcomes"), outcome))
        self.outcome = outcome
        self.executions = 0

    def execute(self, userdata: UserDataAccess) -> str:
        """Return the fixed outcome."""
        self.executions += 1
        return self.outcome


class SucceedState(FixedOutcome):
    """Returns ``"succeeded"``."""

    def __init__(self, outcomes: Sequence[str] = ()) -> None:
        super().__init__("succeeded", outcomes)


class FailState(FixedOutcome):
    """Returns ``"aborted"``."""

    def __init__(self, outcomes: Sequence[str] = ()) -> None:
        super().__init__("aborted", outcomes)


class OutcomeQueue(State):
    """Returns scripted outcomes in turn, like py_trees' StatusQueue.

    Args:
        queue: The outcomes of the first runs, in order.
        eventually: The outcome of every later run; None repeats ``queue`` from the start.
        outcomes: Extra declared outcomes (those in ``queue`` and ``eventually`` are added).
    """

    def __init__(
        self, queue: Sequence[str], eventually: str | None = None, outcomes: Sequence[str] = ()
    ) -> None:
        names(queue, "queue")  # validates
        script = tuple(queue)
        if not script:
            raise InvalidStateError("OutcomeQueue needs at least one outcome in its queue")
        tail = (eventually,) if eventually is not None else ()
        super().__init__((*names(outcomes, "outcomes"), *script, *tail))
        self._script = script
        self._eventually = eventually
        self.executions = 0

    def execute(self, userdata: UserDataAccess) -> str:
        """Return the next scripted outcome."""
        n, self.executions = self.executions, self.executions + 1
        if n < len(self._script):
            return self._script[n]
        if self._eventually is not None:
            return self._eventually
        return self._script[n % len(self._script)]


class RaiseState(State):
    """Raises ``error`` when executed (to test error reporting)."""

    def __init__(self, error: Exception, outcomes: Sequence[str] = ("succeeded",)) -> None:
        super().__init__(outcomes)
        self.error = error

    def execute(self, userdata: UserDataAccess) -> str:
        """Raise the configured error."""
        raise self.error


class WaitForPreempt(State):
    """Blocks until preempted, or until a test calls `release`; never sleeps.

    `entered` is set when `execute` starts, so a test can wait for the state to be
    running (``assert state.entered.wait(5)``) before preempting it.

    Args:
        outcomes: Declared outcomes; ``"preempted"`` is added.
        input_keys: Keys declared as read (not read).
        output_keys: Keys declared as written (not written).
        services: False makes the state return ``"preempted"`` without calling
            `service_preempt`, to test how containers treat an ignored request.
    """

    def __init__(
        self,
        outcomes: Sequence[str] = (),
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
        services: bool = True,
    ) -> None:
        super().__init__((*names(outcomes, "outcomes"), "preempted"), input_keys, output_keys)
        self.entered = threading.Event()
        self.executions = 0
        self._services = services
        self._wake = threading.Event()
        self._lock = threading.Lock()
        self._released: str | None = None

    def release(self, outcome: str) -> None:
        """End the current (or next) run with ``outcome`` instead of waiting for a preempt."""
        if outcome not in self.outcomes:
            raise InvalidStateError(
                f"cannot release {self.describe()} with {outcome!r}; outcomes: {listing(self.outcomes)}"
            )
        with self._lock:
            self._released = outcome
        self._wake.set()

    def request_preempt(self) -> None:
        """Set the preempt flag and wake `execute`."""
        super().request_preempt()
        self._wake.set()

    def execute(self, userdata: UserDataAccess) -> str:
        """Wait for a preempt (outcome ``"preempted"``) or a `release`."""
        self.executions += 1
        self.entered.set()
        while True:
            if self.preempt_requested():
                if self._services:
                    self.service_preempt()
                return "preempted"
            with self._lock:
                released, self._released = self._released, None
            if released is not None:
                return released
            self._wake.wait()
            self._wake.clear()
