"""`SimpleActionState`: send an action goal built from userdata, wait for it, cancel on preempt."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from ..action import ActionClient, ClientGoalHandle, GoalResult, GoalStatus
from ..errors import (
    ActionError,
    GoalRejectedError,
    InvalidStateError,
    ZenrosTimeout,
)
from ..message import ActionType, Message
from .ros_state import RosState, build_message, check_slots, read_slots, slot_keys
from .userdata import UserDataAccess

if TYPE_CHECKING:
    from ..node import Node

__all__ = ["SimpleActionState"]

GoalCb = Callable[[UserDataAccess, Any], Any]
ResultCb = Callable[[UserDataAccess, GoalStatus, Any], str | None]
FeedbackCb = Callable[[UserDataAccess, Any], Any]

_SENT_BY_SERVER = (GoalStatus.SUCCEEDED, GoalStatus.CANCELED, GoalStatus.ABORTED)


class SimpleActionState(RosState):
    """Run one goal of action ``name`` to its end, as smach_ros's SimpleActionState.

    The goal starts from ``goal`` (default: an empty ``action_type.Goal``) or from
    ``userdata[goal_key]``; ``goal_slots`` fields are set from same-named userdata keys;
    ``goal_cb(userdata, goal)`` may return a new goal (or None to keep it). The state
    waits up to ``server_wait_timeout`` seconds for a server, sends the goal and blocks
    until the goal ends.

    Outcomes, from the goal's end: SUCCEEDED gives ``"succeeded"``; CANCELED gives
    ``"preempted"`` if this state asked for it (a preempt) and ``"aborted"`` otherwise;
    ABORTED, a rejected goal, a server that dies mid-goal (LOST) or none in time give
    ``"aborted"``. A preempt cancels the goal and waits up to ``preempt_timeout`` for it to
    end; a goal that still succeeds wins, and the preempt is left to the container. After
    ``exec_timeout`` seconds the goal is cancelled too, and the outcome is ``"aborted"``.

    The result is stored under ``result_key`` and its ``result_slots`` fields under their
    own names; ``result_cb(userdata, status, result)`` may return another outcome (declare
    it in ``outcomes`` or with `cb_interface`). ``feedback_cb(userdata, feedback)`` sees
    each feedback message.

    Example:
        >>> SimpleActionState(node, NavigateToPose, "navigate_to_pose",
        ...                   goal_slots=["pose"], result_slots=["error_code"])

    Args:
        node: The node that owns the action client.
        action_type: The action type.
        name: The action name (resolved against the node).
        goal: The goal template (copied, never changed).
        goal_cb: Builds or adjusts the goal.
        goal_key: Userdata key holding the whole goal.
        goal_slots: Goal fields read from same-named userdata keys.
        result_cb: Looks at the end of the goal; may return an outcome.
        result_key: Userdata key that receives the whole result.
        result_slots: Result fields written to same-named userdata keys.
        feedback_cb: Called with each feedback (on a Zenoh thread).
        input_keys: More keys the callbacks read.
        output_keys: More keys the callbacks write.
        outcomes: More outcomes ``result_cb`` may return.
        exec_timeout: Seconds the goal may run; None: no limit.
        preempt_timeout: Seconds to wait for a cancelled goal to end.
        server_wait_timeout: Seconds to wait for a server on each run.
    """

    def __init__(
        self,
        node: Node,
        action_type: ActionType,
        name: str,
        goal: Message | None = None,
        *,
        goal_cb: GoalCb | None = None,
        goal_key: str | None = None,
        goal_slots: Sequence[str] = (),
        result_cb: ResultCb | None = None,
        result_key: str | None = None,
        result_slots: Sequence[str] = (),
        feedback_cb: FeedbackCb | None = None,
        input_keys: Sequence[str] = (),
        output_keys: Sequence[str] = (),
        outcomes: Sequence[str] = (),
        exec_timeout: float | None = None,
        preempt_timeout: float = 5.0,
        server_wait_timeout: float = 5.0,
    ) -> None:
        if goal is not None and type(goal) is not action_type.Goal:
            raise InvalidStateError(
                f"SimpleActionState for {name}: goal must be {action_type.Goal.__name__},"
                f" got {type(goal).__name__}")
        check_slots("SimpleActionState", action_type.Goal, goal_slots, "goal_slots")
        check_slots("SimpleActionState", action_type.Result, result_slots, "result_slots")
        super().__init__(
            node, ("succeeded", "aborted", "preempted", *outcomes),
            slot_keys(goal_slots, goal_key, input_keys),
            slot_keys(result_slots, result_key, output_keys),
            callbacks=(goal_cb, result_cb, feedback_cb),
        )
        self.action_type = action_type
        self.client = ActionClient(node, action_type, name)
        self._goal = goal
        self._goal_cb = goal_cb
        self._goal_key = goal_key
        self._goal_slots = tuple(goal_slots)
        self._result_cb = result_cb
        self._result_key = result_key
        self._result_slots = tuple(result_slots)
        self._feedback_cb = feedback_cb
        self._exec_timeout = exec_timeout
        self._preempt_timeout = preempt_timeout
        self._server_wait = server_wait_timeout

    @property
    def name(self) -> str:
        """The resolved action name."""
        return self.client.name

    def execute(self, userdata: UserDataAccess) -> str:
        """Send the goal and wait for its end; see the class docstring for the outcomes."""
        if self.take_preempt():
            return "preempted"
        goal = self._build(userdata)
        missing = self.await_server(self.client.server_is_ready, f"action {self.name}",
                                    self._server_wait)
        if missing is not None:
            return missing
        feedback = None
        if self._feedback_cb is not None:
            cb = self._feedback_cb
            feedback = lambda msg: cb(userdata, msg.feedback)
        handle = self.client.send_goal_async(goal, feedback)
        handle.add_done_callback(lambda _h: self.notify())
        timed_out = False
        if not self.wait_until(lambda: handle.done, self._exec_timeout):
            timed_out = not self.preempt_requested()
            if not self._cancel(handle, "its exec_timeout passed" if timed_out else "preempted"):
                if timed_out:
                    return "aborted"
                self.service_preempt()
                return "preempted"
        return self._outcome(userdata, handle, timed_out)

    def _cancel(self, handle: ClientGoalHandle, why: str) -> bool:
        """Cancel the goal and wait for its end; False if it did not end in time."""
        try:
            if handle.accepted is None:
                handle.wait_accepted(self._preempt_timeout)
            if not handle.done:
                handle.cancel(self._preempt_timeout)
        except (ActionError, ZenrosTimeout) as exc:
            self.node.logger.warning("%s: cancelling goal %s (%s) failed: %s",
                                     self.describe(), handle.goal_id, why, exc)
        if self.wait_until(lambda: handle.done, self._preempt_timeout, preemptible=False):
            return True
        self.node.logger.warning("%s: goal %s did not end within %g s of its cancel (%s);"
                                 " leaving it", self.describe(), handle.goal_id,
                                 self._preempt_timeout, why)
        return False

    def _outcome(self, userdata: UserDataAccess, handle: ClientGoalHandle, timed_out: bool) -> str:
        try:
            ended: GoalResult | None = handle.result(0)
        except (GoalRejectedError, ActionError, ZenrosTimeout) as exc:
            self.node.logger.warning("%s: goal on %s failed: %s", self.describe(), self.name, exc)
            ended = None
        status = ended.status if ended is not None else GoalStatus.REJECTED
        if status is GoalStatus.SUCCEEDED:
            outcome = "succeeded"
        elif status is GoalStatus.CANCELED and not timed_out and self.preempt_requested():
            self.service_preempt()
            outcome = "preempted"
        else:
            outcome = "aborted"
            if status is GoalStatus.LOST and ended is not None:
                self.node.logger.warning("%s: %s", self.describe(), ended.reason)
        if ended is not None:
            if status in _SENT_BY_SERVER:
                read_slots(ended.result, userdata, self._result_slots, self._result_key)
            if self._result_cb is not None:
                chosen = self._result_cb(userdata, status, ended.result)
                if chosen is not None:
                    return chosen
        return outcome

    def _build(self, userdata: UserDataAccess) -> Message:
        goal: Message = build_message(
            self, self._goal, self.action_type.Goal, userdata, self._goal_slots,
            self._goal_key, self._goal_cb, "goal", f"action {self.name}")
        return goal
