"""A `Robot` double for the tasks manager: a controllable clock and scripted nav outcomes."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from zenros.services.tasks.manager import TaskManager
from zenros.services.tasks.robot import Feedback, Outcome
from zenros.services.tasks.store import TaskStore


class FakeRobot:
    """Navigation that finishes when the test says so (``arrive``), or at once."""

    def __init__(self) -> None:
        self.said: list[str] = []
        self.goals: list[tuple[float, float, float]] = []
        self.points = [(1.0, 2.0, 0.0), (3.0, 4.0, 1.5)]
        self.auto = True
        self.arrived = threading.Event()
        self.nav_outcome = Outcome("complete", "arrived")
        self.cancels = 0

    def now(self) -> float:
        return time.monotonic()

    def nav_point(self, index: int, map_name: str = "",
                  path_name: str = "") -> tuple[float, float, float]:
        if not 0 <= index < len(self.points):
            raise LookupError(f"no nav point {index}")
        return self.points[index]

    def navigate(self, x: float, y: float, theta: float, timeout: float,
                 feedback: Callable[[Feedback], None],
                 cancelled: Callable[[], bool]) -> Outcome:
        self.goals.append((x, y, theta))
        feedback(Feedback(0.0, 0.0, 0.0, 4.0))
        if self.auto:
            return self.nav_outcome
        while not self.arrived.wait(0.005):
            if cancelled():
                self.cancels += 1
                return Outcome("preempted")
        self.arrived.clear()
        return self.nav_outcome

    def charge(self, pose: Any, level: float, timeout: float,
               cancelled: Callable[[], bool]) -> Outcome:
        return Outcome("complete", "charging")

    def switch_map(self, name: str, path: str, start_index: int) -> Outcome:
        return Outcome("complete", name)

    def say(self, text: str) -> None:
        self.said.append(text)


@pytest.fixture
def robot() -> FakeRobot:
    return FakeRobot()


@pytest.fixture
def events() -> list[tuple[str, str]]:
    return []


@pytest.fixture
def manager(tmp_path: Any, robot: FakeRobot,
            events: list[tuple[str, str]]) -> Iterator[TaskManager]:
    m = TaskManager(TaskStore(tmp_path / "tasks.db"), robot,
                    lambda d, e: events.append((d.state, e)))
    yield m
    m.close()
    m.store.close()
