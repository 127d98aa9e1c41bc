"""The server-side goal state machine (ROS 2's, plus abort of a goal that never started)."""

from __future__ import annotations

from enum import Enum

from ..errors import GoalStateError
from .types import GoalStatus

__all__ = ["GoalEvent", "transition"]


class GoalEvent(Enum):
    """What moves a goal from one state to the next."""

    ACCEPT = "accept"
    EXECUTE = "execute"
    CANCEL_GOAL = "cancel_goal"
    SUCCEED = "succeed"
    ABORT = "abort"
    CANCELED = "canceled"


_S = GoalStatus
_E = GoalEvent

_TABLE: dict[GoalStatus, dict[GoalEvent, GoalStatus]] = {
    _S.UNKNOWN: {_E.ACCEPT: _S.ACCEPTED},
    _S.ACCEPTED: {_E.EXECUTE: _S.EXECUTING, _E.CANCEL_GOAL: _S.CANCELING, _E.ABORT: _S.ABORTED},
    _S.EXECUTING: {_E.CANCEL_GOAL: _S.CANCELING, _E.SUCCEED: _S.SUCCEEDED, _E.ABORT: _S.ABORTED},
    _S.CANCELING: {_E.SUCCEED: _S.SUCCEEDED, _E.ABORT: _S.ABORTED, _E.CANCELED: _S.CANCELED},
}


def transition(state: GoalStatus, event: GoalEvent, goal: object = "") -> GoalStatus:
    """The state after ``event``; raises `GoalStateError` naming what would have been valid."""
    moves = _TABLE.get(state, {})
    try:
        return moves[event]
    except KeyError:
        valid = ", ".join(e.value for e in moves) or "none (the goal has ended)"
        what = f"goal {goal}" if goal else "goal"  # formatted only here: the hot path skips it
        hint = " (cancel was not requested)" if event is _E.CANCELED and moves else ""
        raise GoalStateError(
            f"{what} cannot {event.value} while {state.name}{hint}; valid now: {valid}"
        ) from None
