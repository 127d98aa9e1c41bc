"""ROS 2's lifecycle state machine (rcl's default state machine), without a node.

Primary states (unconfigured, inactive, active, finalized), transition states (configuring,
cleaningup, shuttingdown, activating, deactivating, errorprocessing) and the transitions
between them, with rcl's ids and labels. `StateMachine.trigger` runs one requested
transition: it enters the transition state, calls the callback, follows its outcome
(SUCCESS, FAILURE or ERROR; an exception counts as ERROR) and, on ERROR, runs the error
callback from errorprocessing. Each step is reported, as rcl publishes it on
``~/transition_event``.
"""

from __future__ import annotations

import enum
import threading
from collections.abc import Callable
from dataclasses import dataclass

__all__ = [
    "STATE_LABELS",
    "TRANSITIONS",
    "InvalidTransitionError",
    "LifecycleState",
    "StateMachine",
    "TransitionCallbackReturn",
    "TransitionDef",
]

UNKNOWN, UNCONFIGURED, INACTIVE, ACTIVE, FINALIZED = 0, 1, 2, 3, 4
CONFIGURING, CLEANINGUP, SHUTTINGDOWN, ACTIVATING, DEACTIVATING, ERRORPROCESSING = range(10, 16)

STATE_LABELS: dict[int, str] = {
    UNKNOWN: "unknown", UNCONFIGURED: "unconfigured", INACTIVE: "inactive", ACTIVE: "active",
    FINALIZED: "finalized", CONFIGURING: "configuring", CLEANINGUP: "cleaningup",
    SHUTTINGDOWN: "shuttingdown", ACTIVATING: "activating", DEACTIVATING: "deactivating",
    ERRORPROCESSING: "errorprocessing",
}
PRIMARY_STATES = (UNCONFIGURED, INACTIVE, ACTIVE, FINALIZED)


class TransitionCallbackReturn(enum.IntEnum):
    """What a transition callback returns (lifecycle_msgs' TRANSITION_CALLBACK_*)."""

    SUCCESS = 97
    FAILURE = 98
    ERROR = 99

    def to_label(self) -> str:
        """The label of the outcome transition it selects (rcl's ``transition_success``...)."""
        return f"transition_{self.name.lower()}"


class InvalidTransitionError(ValueError):
    """A transition that does not start from the current state (or names none)."""


@dataclass(frozen=True)
class LifecycleState:
    """A state by label and id (rclpy's ``LifecycleState``)."""

    label: str
    state_id: int

    @classmethod
    def of(cls, state_id: int) -> LifecycleState:
        return cls(STATE_LABELS[state_id], state_id)


@dataclass(frozen=True)
class TransitionDef:
    """One edge of the graph: ``id``/``label`` lead from ``start`` to ``goal``."""

    id: int
    label: str
    start: int
    goal: int


def _requested(tid: int, label: str, start: int, goal: int) -> list[TransitionDef]:
    return [TransitionDef(tid, label, start, goal)]


def _outcomes(base: int, start: int, success: int, failure: int,
              error: int = ERRORPROCESSING) -> list[TransitionDef]:
    return [TransitionDef(base, "transition_success", start, success),
            TransitionDef(base + 1, "transition_failure", start, failure),
            TransitionDef(base + 2, "transition_error", start, error)]


# rcl's registration order (default_state_machine.c)
TRANSITIONS: tuple[TransitionDef, ...] = tuple(
    _requested(1, "configure", UNCONFIGURED, CONFIGURING)
    + _outcomes(10, CONFIGURING, INACTIVE, UNCONFIGURED)
    + _requested(2, "cleanup", INACTIVE, CLEANINGUP)
    + _outcomes(20, CLEANINGUP, UNCONFIGURED, INACTIVE)
    + _requested(3, "activate", INACTIVE, ACTIVATING)
    + _outcomes(30, ACTIVATING, ACTIVE, INACTIVE)
    + _requested(4, "deactivate", ACTIVE, DEACTIVATING)
    + _outcomes(40, DEACTIVATING, INACTIVE, ACTIVE)
    + _requested(5, "shutdown", UNCONFIGURED, SHUTTINGDOWN)
    + _requested(6, "shutdown", INACTIVE, SHUTTINGDOWN)
    + _requested(7, "shutdown", ACTIVE, SHUTTINGDOWN)
    + _outcomes(50, SHUTTINGDOWN, FINALIZED, FINALIZED)
    + _outcomes(60, ERRORPROCESSING, UNCONFIGURED, FINALIZED, FINALIZED)
)

Callback = Callable[[int, LifecycleState], TransitionCallbackReturn]
"""``call(transition_state_id, starting_state)``: runs the node's callback of that state."""
Emit = Callable[[TransitionDef], None]


class StateMachine:
    """The current state and the one transition that may run at a time."""

    def __init__(self) -> None:
        self._state = UNCONFIGURED
        self._lock = threading.RLock()

    @property
    def state(self) -> LifecycleState:
        return LifecycleState.of(self._state)

    @property
    def state_id(self) -> int:
        return self._state

    @staticmethod
    def states() -> list[LifecycleState]:
        return [LifecycleState.of(s) for s in STATE_LABELS]

    def available(self) -> list[TransitionDef]:
        """The transitions that start from the current state."""
        return [t for t in TRANSITIONS if t.start == self._state]

    def find(self, transition_id: int = 0, label: str = "") -> TransitionDef:
        """The requestable transition from the current state named by ``label`` (if given: it
        wins over the id, as rclpy's change_state does) or by ``transition_id``."""
        state = self._state
        if state not in PRIMARY_STATES:
            raise InvalidTransitionError(
                f"a transition is in progress (state {STATE_LABELS[state]})")
        for t in self.available():
            if (t.label == label) if label else (t.id == transition_id):
                return t
        name = repr(label) if label else f"id {transition_id}"
        valid = ", ".join(f"{t.label} [{t.id}]" for t in self.available()) or "none"
        raise InvalidTransitionError(
            f"no transition {name} from state {STATE_LABELS[state]} (valid: {valid})")

    def trigger(self, transition: TransitionDef, call: Callback,
                emit: Emit) -> TransitionCallbackReturn:
        """Run ``transition`` (one `find` gave) with the node's callbacks; returns what the
        callback returned. Emits each step: two, three when the callback returned ERROR."""
        with self._lock:
            start = self._state
            if transition.start != start or start not in PRIMARY_STATES:
                raise InvalidTransitionError(
                    f"transition {transition.label} [{transition.id}] does not start from "
                    f"state {STATE_LABELS[start]}")
            starting = LifecycleState.of(start)
            self._step(transition, emit)
            ret = call(transition.goal, starting)
            self._step(self._outcome(ret), emit)
            if ret is TransitionCallbackReturn.ERROR:
                self._step(self._outcome(call(ERRORPROCESSING, starting)), emit)
            return ret

    def _outcome(self, ret: TransitionCallbackReturn) -> TransitionDef:
        label = ret.to_label()
        return next(t for t in self.available() if t.label == label)

    def _step(self, t: TransitionDef, emit: Emit) -> None:
        self._state = t.goal
        emit(t)
