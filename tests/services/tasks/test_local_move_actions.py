"""local_move_action, local_move_target_action, io_action and the actuator actions: parameter
checks, the legs a local move runs in each method, a resumed move drives only what is left,
a map-frame lift rotation, errors pass on."""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import Any

import pytest
from zenros.msgs.zenros_msgs.task_actions import Action
from zenros.services.tasks.actiontypes import ActionParamsError, action_of, validate_params
from zenros.services.tasks.behaviors import BEHAVIORS, Context
from zenros.services.tasks.robot import Outcome


class MoveRobot:
    """Records the legs and IO sets; each leg reports its progress half way, then ends."""

    def __init__(self) -> None:
        self.calls: list[tuple[Any, ...]] = []
        self.outcome = Outcome("complete")
        self.where: tuple[float, float, float] | None = (0.0, 0.0, 0.0)

    def now(self) -> float:
        return time.monotonic()

    def drive(self, distance: float, speed: float, timeout: float,
              progress: Callable[[float], None], cancelled: Callable[[], bool]) -> Outcome:
        self.calls.append(("drive", round(distance, 6), speed))
        progress(distance / 2)
        return self.outcome

    def spin(self, angle: float, timeout: float, progress: Callable[[float], None],
             cancelled: Callable[[], bool]) -> Outcome:
        self.calls.append(("spin", round(angle, 6)))
        progress(angle / 2)
        return self.outcome

    def local_move_target(self, *args: Any) -> Outcome:
        self.calls.append(("target", *args[:-1]))
        return self.outcome

    def set_io(self, port: int, level: int) -> Outcome:
        self.calls.append(("io", port, level))
        return self.outcome

    def pose(self) -> tuple[float, float, float] | None:
        return self.where

    def move_axis(self, axis: str, mode: int, target: float, speed: float, duration: float,
                  progress: Callable[[float], None],
                  cancelled: Callable[[], bool]) -> Outcome:
        self.calls.append((axis, mode, round(target, 6), speed, round(duration, 6)))
        progress(0.5)
        return self.outcome


def run(robot: MoveRobot, doc: dict[str, Any],
        progress: float = 0.0) -> tuple[Outcome, Action]:
    params = validate_params(doc)
    item = action_of(doc["type"], params)
    item.progress = progress
    ctx = Context(robot, item, lambda: False, lambda: None,  # type: ignore[arg-type]
                  threading.Event())
    return BEHAVIORS[doc["type"]](ctx, action_of(doc["type"], params)), item


def test_method_0_moves_then_turns_and_1_turns_then_moves() -> None:
    robot = MoveRobot()
    out, item = run(robot, {"type": "local_move_action", "distance": 0.5, "angle": 1.57})
    assert out.name == "complete" and item.progress == 1.0
    assert robot.calls == [("drive", 0.5, 0.3), ("spin", 1.57)]
    robot.calls.clear()
    run(robot, {"type": "local_move_action", "distance": -0.2, "angle": -1.0, "method": 1})
    assert robot.calls == [("spin", -1.0), ("drive", -0.2, 0.3)]
    robot.calls.clear()
    out, _ = run(robot, {"type": "local_move_action", "angle": 0.5})
    assert robot.calls == [("spin", 0.5)]
    robot.calls.clear()
    out, _ = run(robot, {"type": "local_move_action"})
    assert out.name == "complete" and robot.calls == []


def test_a_resumed_move_drives_what_is_left() -> None:
    robot = MoveRobot()
    run(robot, {"type": "local_move_action", "distance": 1.0, "angle": 2.0}, progress=0.75)
    assert robot.calls == [("spin", 1.0)]  # drive done, half the turn done
    robot.calls.clear()
    run(robot, {"type": "local_move_action", "distance": 1.0, "angle": 2.0}, progress=0.25)
    assert robot.calls == [("drive", 0.5, 0.3), ("spin", 2.0)]


def test_a_failed_leg_ends_the_action() -> None:
    robot = MoveRobot()
    robot.outcome = Outcome("error", "drive 0.50 m: aborted (error 723: collision ahead)")
    out, _ = run(robot, {"type": "local_move_action", "distance": 0.5, "angle": 1.0})
    assert out.name == "error" and "collision ahead" in out.reason
    assert robot.calls == [("drive", 0.5, 0.3)]


def test_target_and_io_actions() -> None:
    robot = MoveRobot()
    out, _ = run(robot, {"type": "local_move_target_action", "x": 1, "y": 2, "theta": 0.5,
                         "frame_id": "base_link", "start_rotate_enable": False})
    assert out.name == "complete"
    assert robot.calls == [("target", 1.0, 2.0, 0.5, "base_link", 0.05, 0.05, 0.0, False,
                            True)]
    robot.calls.clear()
    run(robot, {"type": "io_action", "level": "1", "port": "3"})
    assert robot.calls == [("io", 3, 1)]


def test_actuator_actions_move_their_axis() -> None:
    robot = MoveRobot()
    out, item = run(robot, {"type": "slide_action", "pose": 0.5})
    assert out.name == "complete" and robot.calls == [("slide", 3, 0.5, 0.0, 0.0)]
    assert item.progress == 0.5  # what the link reported
    robot.calls.clear()
    run(robot, {"type": "jacking_action", "mode": 1, "speed": -0.02, "time": 4})
    assert robot.calls == [("jacking", 1, 0.0, -0.02, 4.0)]
    robot.calls.clear()
    # a resumed speed move runs the time its progress leaves, and reports on the whole
    _, item = run(robot, {"type": "jacking_action", "mode": 1, "time": 4}, progress=0.75)
    assert robot.calls == [("jacking", 1, 0.0, 0.0, 1.0)] and item.progress == 0.875
    robot.calls.clear()
    run(robot, {"type": "jacking_rotate_action", "angle": 1.0})  # base_link by default
    assert robot.calls == [("jacking_rotation", 3, 1.0, 0.0, 0.0)]
    robot.calls.clear()
    robot.where = (2.0, 1.0, 3.0)  # heading 3 rad on the map: map 1.0 is -2.0 in base_link
    run(robot, {"type": "jacking_rotate_action", "angle": 1.0, "frame_id": "map",
                "speed": 0.5})
    assert robot.calls == [("jacking_rotation", 3, -2.0, 0.5, 0.0)]
    robot.calls.clear()
    robot.where = (0.0, 0.0, -3.0)  # map 3.0 is 6.0 rad away: wrapped to 6 - 2 pi
    run(robot, {"type": "jacking_rotate_action", "angle": 3.0, "frame_id": "map"})
    assert robot.calls == [("jacking_rotation", 3, round(6.0 - 2 * math.pi, 6), 0.0, 0.0)]
    robot.where = None
    out, _ = run(robot, {"type": "jacking_rotate_action", "angle": 1.0, "frame_id": "map"})
    assert out.name == "error" and "pose in map is unknown" in out.reason
    robot.outcome = Outcome("error", "slide at 1 for 5 s: slide reached its high limit (1)")
    out, _ = run(robot, {"type": "slide_action", "mode": 1, "speed": 0.3, "time": 5})
    assert out.name == "error" and "high limit" in out.reason


@pytest.mark.parametrize("doc", [
    {"type": "slide_action", "mode": 4},
    {"type": "slide_action", "pose": "0.5"},
    {"type": "slide_action", "time": -1},
    {"type": "jacking_action", "pose": float("nan")},
    {"type": "jacking_rotate_action", "frame_id": "odom"},
    {"type": "jacking_rotate_action", "pose": 0.1},
    {"type": "local_move_action", "method": 2},
    {"type": "local_move_action", "distance": "1"},
    {"type": "local_move_action", "distance": 100},
    {"type": "local_move_action", "angle": float("inf")},
    {"type": "local_move_target_action", "x": 1},
    {"type": "local_move_target_action", "x": 1, "y": 1, "frame_id": "odom"},
    {"type": "local_move_target_action", "x": 1, "y": 1, "xy_tolerance": 0},
    {"type": "io_action", "level": "2", "port": "1"},
    {"type": "io_action", "level": "1", "port": "0"},
    {"type": "io_action", "level": 1, "port": "1"},
    {"type": "io_action", "level": "1"},
])
def test_bad_parameters_are_named(doc: dict[str, Any]) -> None:
    with pytest.raises(ActionParamsError, match=doc["type"]):
        validate_params(doc)
