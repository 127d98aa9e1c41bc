"""`Context`: what a running action's behaviour may touch (its robot, its document, its
task's cancel request, progress, the ``update_wait_req`` release, cleanups for its task's
end)."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Final

from zenros.msgs.zenros_msgs.task_actions import Action

from .robot import Robot

__all__ = ["POLL", "Context"]

POLL: Final = 0.01  # wall seconds between checks while waiting


def _run_now(cleanup: Callable[[], None]) -> None:
    cleanup()


class Context:
    """What a running behaviour may touch: the robot, its item, progress and release.

    ``at_end(cleanup)`` has ``cleanup`` called once the enclosing (root) task ends: complete,
    failed, stopped, deleted, or the tasks service stopping; a pause is no end. Without a
    task around it (a behaviour run by hand) the cleanup runs at once."""

    def __init__(self, robot: Robot, item: Action, cancelled: Callable[[], bool],
                 changed: Callable[[], None], wait_release: threading.Event,
                 at_end: Callable[[Callable[[], None]], None] = _run_now) -> None:
        self.robot = robot
        self.item = item
        self.cancelled = cancelled
        self.changed = changed
        self.wait_release = wait_release
        self.at_end = at_end

    def progress(self, value: float) -> None:
        self.item.progress = round(max(0.0, min(1.0, value)), 4)
        self.changed()

    def wait(self, seconds: float) -> bool:
        """Wait ``seconds`` of the robot's clock; False when cancelled first."""
        if seconds <= 0:
            return not self.cancelled()
        done = float(self.item.progress)  # a resumed wait keeps what it waited
        start = self.robot.now() - done * seconds
        end = start + seconds
        event = threading.Event()
        while True:
            if self.cancelled():
                return False
            now = self.robot.now()
            if now >= end:
                return True
            self.item.progress = round((now - start) / seconds, 4)
            event.wait(min(POLL, end - now))
