"""The task store: a `Task` Struct per row, rows of the earlier plain form still read (an
upgrade keeps a user's tasks), unreadable rows skipped and named."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path
from typing import Any

import msgspec
from zenros.msgs.zenros_msgs.task_actions import NavAction, SleepAction
from zenros.msgs.zenros_msgs.task_docs import SubTask, Task, as_document
from zenros.services.tasks.documents import new_task
from zenros.services.tasks.manager import TaskManager
from zenros.services.tasks.store import TaskStore
from zenros.testing import wait_for

_SLEEP = {"id": "a2", "type": "sleep_action", "wait_time": 0.01, "state": "WORKING",
          "result": "", "progress": 0.4}
# a row as the store wrote it while documents were plain dicts: nested tasks carry no
# "type", current_task is a copy of the running action
OLD_ROW: dict[str, Any] = {
    "id": "t1", "name": "patrol", "sub_tasks": [
        {"id": "a1", "type": "nav_action", "x": 1.0, "y": 2.0, "theta": 0.5, "map": "",
         "path": "", "timeout": 0.0, "state": "COMPLETE", "result": "arrived",
         "progress": 1.0, "current_location": {"x": 1.0, "y": 2.0, "theta": 0.5},
         "current_distance": 0.0},
        {"id": "n1", "name": "inner", "sub_tasks": [_SLEEP], "loop_flag": False,
         "loop_count": 0, "state": "WORKING", "progress": 0.4, "current_task": _SLEEP,
         "control_type": "sequence", "blackboard": {}}],
    "loop_flag": False, "loop_count": 0, "state": "WORKING", "progress": 0.7,
    "current_task": _SLEEP, "control_type": "sequence", "blackboard": {"who": "me"}}
DONE_ROW: dict[str, Any] = {
    "id": "t0", "name": "done", "sub_tasks": [], "loop_flag": True, "loop_count": 3,
    "state": "ERROR", "progress": 0.0, "current_task": None, "control_type": "sequence",
    "blackboard": {}, "result": "failed"}


def _write_rows(path: Path, rows: list[tuple[str, bytes]]) -> None:
    TaskStore(path).close()  # the schema
    db = sqlite3.connect(str(path))
    with db:
        for seq, (task_id, data) in enumerate(rows, 1):
            db.execute("INSERT INTO tasks(id, seq, doc) VALUES(?, ?, ?)", (task_id, seq, data))
    db.close()


def test_rows_of_the_plain_form_load_as_tasks(tmp_path: Path, robot: Any) -> None:  # conftest.FakeRobot
    path = tmp_path / "tasks.db"
    _write_rows(path, [("t0", json.dumps(DONE_ROW).encode()),
                       ("t1", json.dumps(OLD_ROW).encode())])
    store = TaskStore(path)
    done, doc = store.load()
    assert store.bad_rows == []
    assert isinstance(doc, Task) and isinstance(doc.sub_tasks[1], SubTask)
    assert isinstance(doc.sub_tasks[0], NavAction) and isinstance(doc.current_task, SleepAction)
    assert as_document(doc) == OLD_ROW and as_document(done) == DONE_ROW
    m = TaskManager(store, robot)
    try:
        # the WORKING task comes back PAUSED, as before the upgrade
        assert m.recovered == ["t1"]
        paused = as_document(m.get("t1"))
        assert paused["state"] == "PAUSED"
        assert paused["sub_tasks"][1]["state"] == "PAUSED"
        assert paused["sub_tasks"][1]["sub_tasks"][0]["state"] == "PAUSED"
        m.resume("t1")
        assert wait_for(lambda: m.get("t1").state == "COMPLETE", 10), m.get("t1")
        assert robot.goals == []  # the completed nav action is not driven again
    finally:
        m.close()
        store.close()
    # the row was rewritten in the Struct's form (nested tasks tagged) and reads back
    db = sqlite3.connect(str(path))
    data = db.execute("SELECT doc FROM tasks WHERE id='t1'").fetchone()[0]
    db.close()
    assert json.loads(data)["sub_tasks"][1]["type"] == "task"
    again = TaskStore(path)
    try:
        assert [t.id for t in again.load()] == ["t0", "t1"]
        assert again.load()[1].state == "COMPLETE"
    finally:
        again.close()


def test_struct_rows_round_trip(tmp_path: Path) -> None:
    store = TaskStore(tmp_path / "tasks.db")
    doc = new_task({"name": "n", "blackboard": {"k": 1}, "sub_tasks": [
        {"type": "nav_action", "index": 1},
        {"name": "inner", "control_type": "loop", "target_loop_count": 2,
         "sub_tasks": [{"type": "tts_action", "text": "{k}"}]}]})
    store.put(doc)
    try:
        assert store.load() == [doc]
        assert msgspec.json.encode(store.load()[0]) == msgspec.json.encode(doc)
    finally:
        store.close()


def test_unreadable_rows_are_skipped_and_named(tmp_path: Path) -> None:
    path = tmp_path / "tasks.db"
    _write_rows(path, [("junk", b"{not json"), ("shape", b'{"id": "shape", "name": 3}'),
                       ("other", json.dumps({**DONE_ROW, "id": "x"}).encode()),
                       ("t0", json.dumps(DONE_ROW).encode())])
    store = TaskStore(path)
    try:
        assert [t.id for t in store.load()] == ["t0"]
        assert store.bad_rows == ["junk", "shape", "other"]
    finally:
        store.close()
