"""`PassThrough`: ``none_stop_nav_action``'s goals: a ``navigate_to_pose`` goal that counts as
done once the robot is within a radius of its point, and is left running then, so the robot
does not stop there: the next goal replaces it (nav's goal policy preempts the running goal
for a new one), or `stop` cancels it (the task's end)."""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import Any, Final

from zenros.action import ActionClient, GoalStatus
from zenros.errors import ZenrosError
from zenros.msgs.nav2_msgs import NavigateToPoseGoal
from zenros.tf.quaternion import yaw_from_quaternion

from .robot import Feedback, Outcome

__all__ = ["PassThrough"]

POLL: Final = 0.02
SERVER_WAIT: Final = 5.0


class PassThrough:
    """Pass-through goals on ``client`` (nav's ``navigate_to_pose``); ``now`` is the robot's
    clock (s); ``cancel`` cancels a goal handle and waits for its end."""

    def __init__(self, client: ActionClient, now: Callable[[], float],
                 cancel: Callable[[Any, float], None]) -> None:
        self.client = client
        self.now = now
        self.cancel = cancel
        self._lock = threading.Lock()
        self._running: Any = None  # the goal left running after its action completed

    def run(self, goal: NavigateToPoseGoal, radius: float, timeout: float,
            feedback: Callable[[Feedback], None], cancelled: Callable[[], bool]) -> Outcome:
        """Send ``goal``; complete once the robot is within ``radius`` m of its point (the
        goal left running) or the goal succeeded; its failure is an error."""
        p = goal.pose.pose.position
        what = f"pass through ({p.x:.2f}, {p.y:.2f}) within {radius:g} m"
        end = time.monotonic() + SERVER_WAIT
        while not self.client.wait_for_server(0.2):
            if cancelled():
                return Outcome("preempted")
            if time.monotonic() > end:
                return Outcome("error", f"{what}: no {self.client.name} server")
        near = threading.Event()
        closest = [math.inf]

        def on_feedback(msg: Any) -> None:
            fb = msg.feedback
            q = fb.current_pose.pose.orientation
            x, y = fb.current_pose.pose.position.x, fb.current_pose.pose.position.y
            d = math.hypot(x - p.x, y - p.y)
            closest[0] = min(closest[0], d)
            feedback(Feedback(x, y, yaw_from_quaternion((q.x, q.y, q.z, q.w)), d))
            if d <= radius:
                near.set()

        start = self.now()
        handle = self.client.send_goal_async(goal, on_feedback)
        while not handle.done:
            if near.is_set():
                with self._lock:
                    self._running = handle
                return Outcome("complete", f"{what}: passing at {closest[0]:.2f} m")
            if cancelled() or (timeout > 0 and self.now() - start > timeout):
                self.cancel(handle, SERVER_WAIT)
                if cancelled():
                    return Outcome("preempted")
                return Outcome("error", f"{what}: not within {radius:g} m in {timeout:g} s")
            threading.Event().wait(POLL)
        try:
            res = handle.result(0)
        except ZenrosError as exc:
            return Outcome("error", f"{what}: {exc}")
        if res.status is GoalStatus.SUCCEEDED:
            return Outcome("complete", f"{what}: reached the point")
        msg = getattr(res.result, "error_msg", "") or res.reason
        return Outcome("error", f"{what}: {res.status.name.lower()}"
                                + (f" ({msg})" if msg else ""))

    def stop(self) -> None:
        """Cancel the goal a completed pass left running, if it still runs (the robot
        stops)."""
        with self._lock:
            handle, self._running = self._running, None
        if handle is not None and not handle.done:
            self.cancel(handle, SERVER_WAIT)
