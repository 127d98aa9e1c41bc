"""What an action leaves until its task ends (`Context.at_end`, `TaskManager._end`): a
``change_setting_action``'s ``init_settings`` are set back when the task completes, is
stopped, is deleted or the service stops; not at a pause, nor between a loop's rounds; and
the elevator actions and ``roslaunch_action`` refuse clearly what they cannot do."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest
from zenros.msgs.zenros_msgs.task_actions import (
    ElevatorReqAction,
    LbtElevatorAckAction,
    RoslaunchAction,
)
from zenros.services.tasks.behaviors import BEHAVIORS, Context
from zenros.services.tasks.launcher import parse_launch_cmd
from zenros.services.tasks.manager import TaskManager
from zenros.services.tasks.robot import Outcome
from zenros.services.tasks.store import TaskStore
from zenros.testing import wait_for


class SettingsRobot:
    """Keeps settings as the gateway would; ``elevators`` None: no building."""

    elevators = None

    def __init__(self) -> None:
        self.settings: dict[str, Any] = {"navigation_speed": 0.5}
        self.launched: list[str] = []

    def now(self) -> float:
        return time.monotonic()

    def change_settings(self, settings: dict[str, Any], check_only: bool = False) -> Outcome:
        bad = [k for k in settings if k not in self.settings]
        if bad:
            return Outcome("error", f"unknown configuration key {bad[0]!r}")
        if not check_only:
            self.settings.update(settings)
        return Outcome("complete", "set")

    def launch(self, launch_cmd: str, cancelled: Any) -> tuple[Outcome, str]:
        return Outcome("error", "not here"), ""


@pytest.fixture
def robot() -> SettingsRobot:
    return SettingsRobot()


@pytest.fixture
def manager(tmp_path: Any, robot: SettingsRobot) -> Iterator[TaskManager]:
    m = TaskManager(TaskStore(tmp_path / "tasks.db"), robot)  # type: ignore[arg-type]
    yield m
    m.close()
    m.store.close()


SLOW = {"type": "change_setting_action", "settings": {"navigation_speed": 0.2},
        "init_settings": {"navigation_speed": 0.5}}


def speed(robot: SettingsRobot) -> float:
    return float(robot.settings["navigation_speed"])


def ended(m: TaskManager, task_id: str) -> bool:
    return m.get(task_id).state in ("COMPLETE", "ERROR", "CANCELLED", "FAILED")


def test_init_settings_come_back_when_the_task_completes(manager: TaskManager,
                                                         robot: SettingsRobot) -> None:
    doc = manager.create({"sub_tasks": [SLOW, {"type": "wait_req_action"}]})
    manager.start(doc.id)
    assert wait_for(lambda: speed(robot) == 0.2, 5)
    manager.release_wait()
    assert wait_for(lambda: ended(manager, doc.id), 5)
    assert manager.get(doc.id).state == "COMPLETE" and speed(robot) == 0.5


def test_a_pause_keeps_them_and_a_stop_sets_them_back(manager: TaskManager,
                                                      robot: SettingsRobot) -> None:
    doc = manager.create({"sub_tasks": [SLOW, {"type": "wait_req_action"}]})
    manager.start(doc.id)
    assert wait_for(lambda: doc.sub_tasks[1].state == "WORKING", 5)
    manager.pause(doc.id)
    assert speed(robot) == 0.2
    manager.stop(doc.id)  # a paused task: settled at once
    assert manager.get(doc.id).state == "CANCELLED" and speed(robot) == 0.5


@pytest.mark.parametrize("end", ["delete", "close"])
def test_deleting_the_task_or_stopping_the_service_sets_them_back(
        manager: TaskManager, robot: SettingsRobot, end: str) -> None:
    doc = manager.create({"sub_tasks": [SLOW, {"type": "wait_req_action"}]})
    manager.start(doc.id)
    assert wait_for(lambda: doc.sub_tasks[1].state == "WORKING", 5)
    if end == "delete":
        manager.pause(doc.id)
        manager.delete(doc.id)
    else:
        manager.close()
    assert speed(robot) == 0.5


def test_a_looping_task_sets_them_back_only_when_it_ends(manager: TaskManager,
                                                         robot: SettingsRobot) -> None:
    doc = manager.create({"loop_flag": True, "sub_tasks": [SLOW]})
    manager.start(doc.id)
    assert wait_for(lambda: manager.get(doc.id).loop_count >= 3, 10)
    assert speed(robot) == 0.2
    manager.stop(doc.id)
    assert speed(robot) == 0.5


def test_a_bad_init_setting_changes_nothing(manager: TaskManager,
                                            robot: SettingsRobot) -> None:
    doc = manager.create({"sub_tasks": [{"type": "change_setting_action",
                                         "settings": {"navigation_speed": 0.2},
                                         "init_settings": {"warp": 1}}]})
    manager.start(doc.id)
    assert wait_for(lambda: ended(manager, doc.id), 5)
    done = manager.get(doc.id)
    assert done.state == "ERROR" and "init_settings: unknown configuration key 'warp'" in \
        done.sub_tasks[0].result
    assert speed(robot) == 0.5


def run_alone(robot: SettingsRobot, action: Any) -> Outcome:
    ctx = Context(robot, action, lambda: False, lambda: None,  # type: ignore[arg-type]
                  threading.Event())
    return BEHAVIORS[str(action.__struct_config__.tag)](ctx, action)


def test_elevator_actions_without_a_building_or_a_request(robot: SettingsRobot) -> None:
    out = run_alone(robot, ElevatorReqAction(level=2))
    assert out.name == "error" and "no building" in out.reason and "building:=" in out.reason
    out = run_alone(robot, LbtElevatorAckAction())
    assert out.name == "error" and "nothing to acknowledge" in out.reason


def test_a_refused_launch_leaves_nothing_to_stop(robot: SettingsRobot) -> None:
    out = run_alone(robot, RoslaunchAction(launch_cmd="sim.yaml"))
    assert out == Outcome("error", "not here")


@pytest.mark.parametrize(("cmd", "parsed"), [
    ("roslaunch xiaoqiang_track xiaoqiang_track.launch", ("xiaoqiang_track", {})),
    ("roslaunch zenros sim.launch speed:=10 map:=office", ("sim", {"speed": "10",
                                                                   "map": "office"})),
    ("zenros launch building.yaml speed:=2", ("building", {"speed": "2"})),
    ("fleet robots:=2", ("fleet", {"robots": "2"})),
])
def test_launch_commands_name_a_file_and_its_arguments(cmd: str,
                                                       parsed: tuple[str, Any]) -> None:
    assert parse_launch_cmd(cmd) == parsed


@pytest.mark.parametrize("cmd", ["roslaunch pkg ../../etc/x.launch", "sim.yaml && reboot",
                                 "roslaunch pkg sim.launch --screen", "bash -c sim",
                                 "sim.yaml speed:=$(reboot)", ""])
def test_anything_else_is_refused(cmd: str) -> None:
    with pytest.raises(ValueError, match="launch_cmd"):
        parse_launch_cmd(cmd)
