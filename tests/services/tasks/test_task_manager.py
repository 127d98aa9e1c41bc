"""The task manager with a robot double: runs, pause/resume/stop, loops, control types,
persistence across a restart, and the refusals."""

from __future__ import annotations

import http.server
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any, ClassVar

import pytest
from conftest import FakeRobot
from zenros.msgs.zenros_msgs.task_docs import Task
from zenros.services.tasks.documents import DocumentError, kind_of
from zenros.services.tasks.manager import TaskBusyError, TaskManager, UnknownTaskError
from zenros.services.tasks.robot import Outcome
from zenros.services.tasks.states import TaskStateError
from zenros.services.tasks.store import TaskStore
from zenros.testing import wait_for

SLEEP = {"type": "sleep_action", "wait_time": 0}
NAV = {"type": "nav_action", "x": 1.0, "y": 2.0, "theta": 0.5}


def _state(m: TaskManager, task_id: str, state: str, timeout: float = 10) -> Task:
    assert wait_for(lambda: m.get(task_id).state == state, timeout), m.get(task_id)
    return m.get(task_id)


def test_sequence_runs_to_complete(manager: TaskManager, robot: FakeRobot,
                                   events: list[tuple[str, str]]) -> None:
    doc = manager.create({"name": "t", "sub_tasks": [SLEEP, NAV, {"type": "tts_action",
                                                                  "text": "done"}]})
    manager.start(doc.id)
    done = _state(manager, doc.id, "COMPLETE")
    assert done.progress == 1.0
    assert [a.state for a in done.sub_tasks] == ["COMPLETE"] * 3
    assert robot.goals == [(1.0, 2.0, 0.5)] and robot.said == ["done"]
    assert ("WORKING", "started") in events and events[-1] == ("COMPLETE", "finished")


def test_nav_point_index_and_unknown_index(manager: TaskManager, robot: FakeRobot) -> None:
    doc = manager.create({"sub_tasks": [{"type": "nav_action", "index": 1},
                                        {"type": "nav_action", "index": 7}]})
    manager.start(doc.id)
    failed = _state(manager, doc.id, "ERROR")
    assert robot.goals == [(3.0, 4.0, 1.5)]
    assert failed.sub_tasks[1].state == "ERROR"
    assert "no nav point 7" in failed.sub_tasks[1].result
    assert "no nav point 7" in failed.result


def test_pause_holds_resume_continues_same_action(manager: TaskManager,
                                                  robot: FakeRobot) -> None:
    robot.auto = False
    doc = manager.create({"sub_tasks": [SLEEP, NAV, SLEEP]})
    manager.start(doc.id)
    assert wait_for(lambda: len(robot.goals) == 1, 5)
    paused = manager.pause(doc.id)
    assert paused.state == "PAUSED" and robot.cancels == 1
    assert [a.state for a in paused.sub_tasks] == ["COMPLETE", "PAUSED", "WAITTING"]
    manager.resume(doc.id)
    assert wait_for(lambda: len(robot.goals) == 2, 5)
    assert robot.goals[1] == robot.goals[0]  # the same nav goal again, not the next one
    robot.arrived.set()
    done = _state(manager, doc.id, "COMPLETE")
    assert [a.state for a in done.sub_tasks] == ["COMPLETE"] * 3


def test_stop_cancels_running_nav(manager: TaskManager, robot: FakeRobot) -> None:
    robot.auto = False
    doc = manager.create({"sub_tasks": [NAV, SLEEP]})
    manager.start(doc.id)
    assert wait_for(lambda: len(robot.goals) == 1, 5)
    stopped = manager.stop()  # no id: the running task
    assert stopped.state == "CANCELLED" and robot.cancels == 1
    assert [a.state for a in stopped.sub_tasks] == ["CANCELLED", "WAITTING"]
    assert manager.running == ""


def test_refusals(manager: TaskManager, robot: FakeRobot) -> None:
    robot.auto = False
    a = manager.create({"sub_tasks": [NAV]})
    b = manager.create({"sub_tasks": [SLEEP]})
    with pytest.raises(TaskStateError, match="cannot pause"):
        manager.pause(a.id)
    manager.start(a.id)
    with pytest.raises(TaskStateError, match="already running"):
        manager.start(a.id)
    with pytest.raises(TaskBusyError, match=a.id):
        manager.start(b.id)
    with pytest.raises(TaskStateError, match="delete"):
        manager.delete(a.id)
    with pytest.raises(TaskStateError):
        manager.update(a.id, {"sub_tasks": []})
    with pytest.raises(UnknownTaskError, match="nope"):
        manager.start("nope")
    with pytest.raises(DocumentError, match="'id'"):
        manager.start("")
    manager.stop(a.id)


def test_failed_create_changes_nothing(manager: TaskManager) -> None:
    before = manager.store.load()
    with pytest.raises(DocumentError):
        manager.create({"sub_tasks": [SLEEP, {"type": "fly"}]})
    assert manager.store.load() == before and manager.tasks() == []


def test_loop_counts_until_stopped(manager: TaskManager) -> None:
    doc = manager.create({"loop_flag": True, "sub_tasks": [
        {"type": "sleep_action", "wait_time": 0.01}]})
    manager.start(doc.id)
    assert wait_for(lambda: manager.get(doc.id).loop_count >= 3, 10)
    manager.stop(doc.id)
    after = manager.get(doc.id)
    assert after.state == "CANCELLED" and after.loop_count >= 3


@pytest.mark.parametrize("control, outcomes, expect", [
    ("sequence", ["complete", "fail", "complete"], "FAILED"),
    ("fallback", ["fail", "complete", "fail"], "COMPLETE"),
    ("fallback", ["fail", "fail"], "FAILED"),
    ("flip", ["fail"], "COMPLETE"),
    ("flip", ["complete"], "FAILED"),
    ("force_success", ["fail"], "COMPLETE"),
    ("force_fail", ["complete"], "FAILED"),
    ("sequence", ["complete", "error"], "ERROR"),
    ("retry_until_success", ["fail", "fail", "complete"], "COMPLETE"),
    ("retry_sequence", ["complete", "fail", "complete"], "COMPLETE"),
    ("parallel", ["complete", "fail", "complete"], "COMPLETE"),
    ("loop", ["complete", "complete", "complete"], "COMPLETE"),
])
def test_control_types(manager: TaskManager, robot: FakeRobot, control: str,
                       outcomes: list[str], expect: str) -> None:
    script = iter(outcomes)
    lock = threading.Lock()

    def navigate(*_: Any) -> Outcome:
        with lock:
            name = next(script, "complete")
        return Outcome(name, name)  # type: ignore[arg-type]

    robot.navigate = navigate  # type: ignore[method-assign]
    n = {"flip": 1, "force_success": 1, "force_fail": 1, "retry_until_success": 1,
         "loop": 1}.get(control, len(outcomes))
    if control == "retry_sequence":
        n = 2
    body: dict[str, Any] = {"control_type": control, "sub_tasks": [NAV] * n}
    if control == "parallel":
        body["success_count"] = 2
    if control == "loop":
        body["target_loop_count"] = 3
    doc = manager.create(body)
    manager.start(doc.id)
    assert wait_for(lambda: manager.get(doc.id).state not in ("WORKING",), 10)
    assert manager.get(doc.id).state == expect


def test_restart_loses_nothing_and_working_comes_back_paused(
        tmp_path: Path, robot: FakeRobot) -> None:
    old_robot = FakeRobot()
    m = TaskManager(TaskStore(tmp_path / "t.db"), old_robot)
    done = m.create({"sub_tasks": [SLEEP]})
    m.start(done.id)
    _state(m, done.id, "COMPLETE")
    old_robot.auto = False
    doc = m.create({"name": "patrol", "sub_tasks": [SLEEP, NAV, SLEEP]})
    m.start(doc.id)
    assert wait_for(lambda: len(old_robot.goals) == 1, 5)
    # a second manager opens the store as a restarted process would (the first one is
    # still mid-task, as a killed one would have been)
    m2 = TaskManager(TaskStore(tmp_path / "t.db"), robot)
    try:
        again = m2.get(doc.id)
        assert again.state == "PAUSED" and m2.recovered == [doc.id]
        assert [a.state for a in again.sub_tasks] == ["COMPLETE", "PAUSED", "WAITTING"]
        assert m2.get(done.id).state == "COMPLETE"
        m2.resume(doc.id)
        _state(m2, doc.id, "COMPLETE")
        assert robot.goals == [(1.0, 2.0, 0.5)]
    finally:
        m.stop(doc.id)
        m.store.close()
        m2.store.close()


def test_wait_req_action_released(manager: TaskManager) -> None:
    doc = manager.create({"sub_tasks": [{"type": "wait_req_action"}, SLEEP]})
    manager.start(doc.id)
    assert wait_for(lambda: manager.get(doc.id).sub_tasks[0].state == "WORKING", 5)
    manager.release_wait()
    _state(manager, doc.id, "COMPLETE")


def test_action_api(manager: TaskManager) -> None:
    task = manager.create_action({"type": "sleep_action", "wait_time": 2})
    assert task.name == "auto task" and task.sub_tasks[0].wait_time == 2
    action_id = task.sub_tasks[0].id
    bigger = manager.create_action({"type": "tts_action", "text": "x", "task_id": task.id})
    assert len(bigger.sub_tasks) == 2
    assert manager.update_action(action_id, {"wait_time": 0}).wait_time == 0
    with pytest.raises(DocumentError, match="wait_time"):
        manager.update_action(action_id, {"wait_time": "soon"})
    manager.delete_action(action_id)
    assert [kind_of(a) for a in manager.get(task.id).sub_tasks] == ["tts_action"]
    with pytest.raises(UnknownTaskError):
        manager.get_action(action_id)


class _Hook(http.server.BaseHTTPRequestHandler):
    hits: ClassVar[list[tuple[str, str, bytes]]] = []

    def do_POST(self) -> None:
        body = self.rfile.read(int(self.headers.get("Content-Length", 0)))
        self.hits.append(("POST", self.path, body))
        self.send_response(204 if self.path == "/ok" else 500)
        self.end_headers()

    def log_message(self, *args: Any) -> None:
        pass


@pytest.fixture
def http_server() -> Iterator[str]:
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Hook)
    t = threading.Thread(target=server.serve_forever, daemon=True)
    t.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


def test_callback_action_hits_http_server(manager: TaskManager, http_server: str) -> None:
    _Hook.hits.clear()
    doc = manager.create({"sub_tasks": [
        {"type": "callback_action", "url": f"{http_server}/ok", "method": "POST",
         "data": {"robot": "r1"}}]})
    manager.start(doc.id)
    done = _state(manager, doc.id, "COMPLETE")
    assert _Hook.hits == [("POST", "/ok", b'{"robot": "r1"}')]
    assert done.sub_tasks[0].result == "HTTP 204"
    bad = manager.create({"sub_tasks": [
        {"type": "callback_action", "url": f"{http_server}/fail", "method": "POST"}]})
    manager.start(bad.id)
    failed = _state(manager, bad.id, "ERROR")
    assert "HTTP 500" in failed.sub_tasks[0].result
