"""ActionBase: what nav's action callbacks share: goal poses into ``map``, running a
behaviour while sending feedback, and settling the goal with Nav2's semantics.

Each execute callback turns its goal into a `Behavior`, hands it to the core's `Motion`
(which halts whatever ran before: a goal of another nav action is aborted, "preempted"),
then waits for it while sending feedback, and settles the goal: SUCCEEDED with error_code
0, ABORTED with the behaviour's error code, or CANCELED. A new goal on the same action
preempts the running one (the action server's ``simple`` policy); like Nav2, the old goal
ends ABORTED with "preempted by a new goal". Goals that are malformed (NaN, a frame other
than ``map``/``odom``/empty, no poses) are rejected at once.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

from zenros.action import ServerGoalHandle
from zenros.errors import GoalRejectedError
from zenros.msgs.builtin_interfaces import Duration, Time
from zenros.msgs.geometry_msgs import PoseStamped
from zenros.se2 import Pose2

from ..core import NavCore
from ..motion.behavior import Behavior
from .convert import pose2_from_msg, pose_stamped

__all__ = ["FEEDBACK_PERIOD", "ActionBase", "ActionOutcome", "AnyGoal", "Ledger"]

FEEDBACK_PERIOD = 0.1  # wall seconds between feedback messages


class ActionOutcome(Protocol):
    """What every nav action result carries: Nav2's error code and message."""

    error_code: int
    error_msg: str


OutcomeT = TypeVar("OutcomeT", bound=ActionOutcome)
AnyGoal = ServerGoalHandle[Any, Any]  # the goal handle of any of nav's actions


class Ledger:
    """What the actions did, for ``nav/status``: the running goal and the last outcome."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.arrivals: dict[str, int] = {}
        self.current: tuple[str, Behavior, Pose2 | None] | None = None
        self.last_outcome: tuple[int, int, str] = (0, 0, "")  # goal_status, code, message


class ActionBase:
    """Helpers of the action callbacks, over one `NavCore`."""

    def __init__(self, core: NavCore, now: Callable[[], Time], logger: logging.Logger,
                 ledger: Ledger) -> None:
        self.core = core
        self.now = now
        self.logger = logger
        self.ledger = ledger

    # ------------------------------------------------------------------ helpers

    def _seconds(self) -> float:
        return self.now().nanoseconds / 1e9

    def _map_pose(self, ps: PoseStamped) -> Pose2:
        """A goal pose in ``map``; raises GoalRejectedError for bad values or frames."""
        try:
            p = pose2_from_msg(ps.pose)
        except ValueError as exc:
            raise GoalRejectedError(f"bad goal pose: {exc}") from None
        frame = ps.header.frame_id.lstrip("/")
        if frame in ("", "map"):
            return p
        if frame == "odom":
            return self.core.localizer.map_to_odom * p
        raise GoalRejectedError(f"goal frame {ps.header.frame_id!r} cannot be transformed "
                                "to map; use 'map' or 'odom'")

    def arrived(self, action: str) -> None:
        """A goal for ``action`` was accepted (called from the goal callbacks)."""
        led = self.ledger
        with led.lock:
            led.arrivals[action] = led.arrivals.get(action, 0) + 1

    def _run(self, action: str, gh: AnyGoal, b: Behavior, goal: Pose2 | None,
             feedback: Callable[[Behavior], Any] | None) -> str:
        """Run ``b`` until it ends or the goal is canceled; ``done``, ``canceled`` or
        ``preempted``."""
        led = self.ledger
        with led.lock:
            arrivals = led.arrivals.get(action, 0)
        led.current = (action, b, goal)
        self.core.start(b)
        try:
            while not b.done.wait(FEEDBACK_PERIOD):
                if gh.is_cancel_requested:
                    with led.lock:
                        newer = led.arrivals.get(action, 0) > arrivals
                    self.core.motion.halt(b, "preempted by a new goal" if newer else "canceled")
                    return "preempted" if newer else "canceled"
                self._feedback(action, gh, b, feedback)
            self._feedback(action, gh, b, feedback)  # the last one says where the goal ended
            return "done"
        finally:
            if led.current is not None and led.current[1] is b:
                led.current = None

    def _feedback(self, action: str, gh: AnyGoal, b: Behavior,
                  feedback: Callable[[Behavior], Any] | None) -> None:
        if feedback is None:
            return
        try:
            gh.publish_feedback(feedback(b))
        except Exception:  # feedback is best effort
            self.logger.debug("feedback for %s failed", action, exc_info=True)

    def _settle(self, gh: AnyGoal, outcome: str, b: Behavior, result: OutcomeT) -> OutcomeT:
        if outcome == "canceled":
            gh.canceled()
            self.ledger.last_outcome = (4, 0, "canceled")
            return result
        if outcome == "preempted":
            result.error_msg = "preempted by a new goal"
            gh.abort()
            self.ledger.last_outcome = (4, 0, result.error_msg)
            return result
        if b.succeeded:
            gh.succeed()
            self.ledger.last_outcome = (2, 0, "")
            return result
        result.error_code, result.error_msg = b.error_code, b.error_msg
        gh.abort()
        self.ledger.last_outcome = (3, b.error_code, b.error_msg)
        return result

    def _nav_times(self, b: Behavior, distance: float) -> tuple[Duration, Duration]:
        now = self._seconds()
        elapsed = 0.0 if b.started_at is None else max(0.0, now - b.started_at)
        v = abs(self.core.speed[0])
        eta = distance / v if v > 0.01 and distance > 0.1 and math.isfinite(distance) else 0.0
        return Duration.from_seconds(elapsed), Duration.from_seconds(eta)

    def _current_pose(self) -> PoseStamped:
        p = self.core.localizer.pose()
        return pose_stamped(p or Pose2(), self.now())
