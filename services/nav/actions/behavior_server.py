"""BehaviorActions: Nav2's behavior server actions ``spin``, ``backup`` and
``drive_on_heading``, and ``local_move_target`` (a planner-free move to a pose).

Goals with non-finite numbers are rejected. Nav2 checks the rest in the server: a bad
DriveOnHeading or BackUp goal (sideways target, zero speed, speed and distance of opposite
signs) ends ABORTED with INVALID_INPUT. Unlike Nav2, a ``time_allowance`` of 0 means no
limit (Nav2 would time out at once). Like the other nav actions, a new goal on any of them
preempts whatever nav was doing (see `base`).
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

from zenros.action import ServerGoalHandle
from zenros.errors import GoalRejectedError
from zenros.msgs.builtin_interfaces import Duration
from zenros.msgs.nav2_msgs import (
    BackUpFeedback,
    BackUpGoal,
    BackUpResult,
    DriveOnHeadingFeedback,
    DriveOnHeadingGoal,
    DriveOnHeadingResult,
    SpinFeedback,
    SpinGoal,
    SpinResult,
)
from zenros.msgs.zenros_msgs.nav import (
    LocalMoveTargetFeedback,
    LocalMoveTargetGoal,
    LocalMoveTargetResult,
)

from ..motion.behavior import Behavior
from ..motion.local_moves import DriveOnHeading, LocalMoveTarget, MoveCodes, SpinInPlace
from .base import ActionBase, ActionOutcome, AnyGoal
from .convert import pose2_from_msg

__all__ = ["BehaviorActions"]


class TimedOutcome(ActionOutcome, Protocol):
    """A local move's result: an outcome and the time the move took."""

    total_elapsed_time: Duration


OutcomeT = TypeVar("OutcomeT", bound=ActionOutcome)
TimedT = TypeVar("TimedT", bound=TimedOutcome)

STOP_WAIT = 2.0  # wall seconds a canceled move waits for the robot to stop
SPIN_CODES = MoveCodes(SpinResult.TIMEOUT, SpinResult.TF_ERROR, SpinResult.COLLISION_AHEAD)
BACKUP_CODES = MoveCodes(BackUpResult.TIMEOUT, BackUpResult.TF_ERROR,
                         BackUpResult.COLLISION_AHEAD)
DRIVE_CODES = MoveCodes(DriveOnHeadingResult.TIMEOUT, DriveOnHeadingResult.TF_ERROR,
                        DriveOnHeadingResult.COLLISION_AHEAD)
TARGET_CODES = MoveCodes(LocalMoveTargetResult.TIMEOUT, LocalMoveTargetResult.TF_ERROR,
                         LocalMoveTargetResult.COLLISION_AHEAD)


def _finite(*values: float) -> bool:
    return all(math.isfinite(v) for v in values)


def _seconds(d: Duration) -> float:
    return max(0.0, float(d.to_sec()))


class BehaviorActions(ActionBase):
    """Goal and execute callbacks of the behavior actions."""

    # ------------------------------------------------------------------ goal checks

    def goal_spin(self, goal: SpinGoal) -> bool:
        if not _finite(goal.target_yaw, goal.time_allowance.to_sec()):
            raise GoalRejectedError("target_yaw and time_allowance must be finite")
        self.arrived("spin")
        return True

    def goal_backup(self, goal: BackUpGoal) -> bool:
        return self._goal_straight("backup", goal)

    def goal_drive_on_heading(self, goal: DriveOnHeadingGoal) -> bool:
        return self._goal_straight("drive_on_heading", goal)

    def _goal_straight(self, action: str, goal: Any) -> bool:
        t = goal.target
        if not _finite(t.x, t.y, t.z, goal.speed, goal.time_allowance.to_sec()):
            raise GoalRejectedError("target, speed and time_allowance must be finite")
        self.arrived(action)
        return True

    def goal_local_move_target(self, goal: LocalMoveTargetGoal) -> bool:
        p = goal.pose.pose
        if not _finite(p.position.x, p.position.y, p.orientation.z, p.orientation.w,
                       goal.xy_tolerance, goal.yaw_tolerance, goal.speed,
                       goal.time_allowance.to_sec()):
            raise GoalRejectedError("pose, tolerances, speed and time_allowance must be "
                                    "finite")
        self.arrived("local_move_target")
        return True

    # ------------------------------------------------------------------ execute

    def execute_spin(self, gh: ServerGoalHandle[SpinGoal, SpinFeedback]) -> SpinResult:
        goal: SpinGoal = gh.request
        speed = self.core.config.nav.spin_speed
        b = SpinInPlace(goal.target_yaw, speed, _seconds(goal.time_allowance), SPIN_CODES)
        return self._go(gh, "spin", b, None,
                        lambda _: SpinFeedback(angular_distance_traveled=b.turned), SpinResult())

    def execute_backup(self, gh: ServerGoalHandle[BackUpGoal, BackUpFeedback]) -> BackUpResult:
        goal: BackUpGoal = gh.request
        result = BackUpResult()
        why = self._straight_problem(goal, backwards=True)
        if why:
            return self._invalid(gh, result, BackUpResult.INVALID_INPUT, why)
        return self._straight(gh, "backup", -abs(goal.target.x), goal, BACKUP_CODES, result,
                              BackUpFeedback)

    def execute_drive_on_heading(
        self, gh: ServerGoalHandle[DriveOnHeadingGoal, DriveOnHeadingFeedback]
    ) -> DriveOnHeadingResult:
        goal: DriveOnHeadingGoal = gh.request
        result = DriveOnHeadingResult()
        why = self._straight_problem(goal, backwards=False)
        if why:
            return self._invalid(gh, result, DriveOnHeadingResult.INVALID_INPUT, why)
        return self._straight(gh, "drive_on_heading", goal.target.x, goal, DRIVE_CODES, result,
                              DriveOnHeadingFeedback)

    def execute_local_move_target(
        self, gh: ServerGoalHandle[LocalMoveTargetGoal, LocalMoveTargetFeedback]
    ) -> LocalMoveTargetResult:
        goal: LocalMoveTargetGoal = gh.request
        result = LocalMoveTargetResult()
        if goal.xy_tolerance <= 0 or goal.yaw_tolerance <= 0 or goal.speed < 0:
            return self._invalid(gh, result, LocalMoveTargetResult.INVALID_INPUT,
                                 "xy_tolerance and yaw_tolerance must be > 0, speed >= 0")
        frame = goal.pose.header.frame_id.lstrip("/")
        relative = frame == "base_link"
        try:
            if relative:
                target = pose2_from_msg(goal.pose.pose)
            else:
                target = self._map_pose(goal.pose)
        except (GoalRejectedError, ValueError) as exc:
            msg = f"{exc} (or 'base_link')" if isinstance(exc, GoalRejectedError) else str(exc)
            return self._invalid(gh, result, LocalMoveTargetResult.INVALID_INPUT, msg)
        ctl = self.core.config.controller
        speed = min(goal.speed or 0.3, ctl.max_linear_vel)
        b = LocalMoveTarget(target, relative, goal.xy_tolerance, goal.yaw_tolerance,
                            _seconds(goal.time_allowance), goal.start_rotate_enable,
                            goal.target_rotate_enable, speed,
                            min(1.0, ctl.max_angular_vel), TARGET_CODES,
                            self.core.config.nav.collision_radius)

        def feedback(_: Behavior) -> LocalMoveTargetFeedback:
            return LocalMoveTargetFeedback(
                current_pose=self._current_pose(),
                distance_remaining=b.distance_remaining(self.core.localizer.pose()))

        return self._go(gh, "local_move_target", b, b.goal, feedback, result)

    # ------------------------------------------------------------------ helpers

    @staticmethod
    def _straight_problem(goal: Any, backwards: bool) -> str:
        t = goal.target
        if t.y != 0 or t.z != 0:
            return "only a target along x is supported (target.y and target.z must be 0)"
        if goal.speed == 0 or t.x == 0:
            return "target.x and speed must be non-zero"
        if not backwards and (t.x < 0) != (goal.speed < 0):
            return "speed and target.x must have the same sign"
        return ""

    def _straight(self, gh: AnyGoal, action: str, distance: float, goal: Any, codes: MoveCodes,
                  result: TimedT, feedback_type: Any) -> TimedT:
        speed = min(abs(goal.speed), self.core.config.controller.max_linear_vel)
        b = DriveOnHeading(distance, speed, _seconds(goal.time_allowance), codes,
                           self.core.config.nav.collision_radius,
                           check_collisions=not goal.disable_collision_checks)
        return self._go(gh, action, b, None,
                        lambda _: feedback_type(distance_traveled=b.traveled), result)

    def _go(self, gh: AnyGoal, action: str, b: Behavior, goal: Any,
            feedback: Callable[[Behavior], Any], result: TimedT) -> TimedT:
        """Run ``b``; a canceled or preempted goal gets one last feedback too, once the robot
        stopped, so the client knows how far it got (a resumed local move drives only the
        rest). A goal that ended gets its last feedback from `_run`."""
        out = self._run(action, gh, b, goal, feedback)
        if out != "done":
            if out == "canceled":
                self._settled_pose(b)
            self._feedback(action, gh, b, feedback)
        result = self._settle(gh, out, b, result)
        t0 = getattr(b, "t0", None)
        if t0 is not None:
            result.total_elapsed_time = Duration.from_seconds(max(0.0, self._seconds() - t0))
        return result

    def _settled_pose(self, b: Behavior) -> None:
        """Wait (2 s at most) for the robot to stop, then let ``b`` measure its pose."""
        end = time.monotonic() + STOP_WAIT
        while time.monotonic() < end:
            v, w = self.core.speed
            if abs(v) < 0.005 and abs(w) < 0.01:
                break
            threading.Event().wait(0.02)
        pose = self.core.localizer.pose()
        if pose is not None and isinstance(b, (DriveOnHeading, SpinInPlace)):
            b.measure(pose)

    def _invalid(self, gh: AnyGoal, result: OutcomeT, code: int, msg: str) -> OutcomeT:
        result.error_code, result.error_msg = code, msg
        gh.abort()
        self.ledger.last_outcome = (3, code, msg)
        return result

