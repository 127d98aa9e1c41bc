"""The ``tasks/*`` calls over the manager: typed requests in, the manager's Structs out as
copies taken at the answer (a running task goes on changing its own)."""

from __future__ import annotations

import msgspec
from zenros.msgs.zenros_msgs import tasks as tm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.task_actions import SleepAction
from zenros.msgs.zenros_msgs.task_docs import Task, as_document
from zenros.services.tasks.api import call
from zenros.services.tasks.manager import TaskManager


def test_calls_answer_snapshots_of_the_manager_structs(manager: TaskManager) -> None:
    req = tm.task_request("create", body={"name": "t", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 1}, {"name": "inner", "sub_tasks": []}]})
    created = call(manager, "create", req)
    assert isinstance(created, tm.TaskResponse) and created.code == ResultCode.OK
    assert isinstance(created.task, Task)
    live = manager.get(created.task.id)
    assert created.task == live and created.task is not live
    got = call(manager, "get", tm.GetTasksRequest(id=live.id))
    assert isinstance(got, tm.GetTasksResponse) and got.tasks == [live]
    action = call(manager, "get_action", tm.GetActionsRequest(id=live.sub_tasks[0].id))
    assert isinstance(action, tm.GetActionsResponse)
    assert isinstance(action.actions[0], SleepAction)
    live.sub_tasks[0].state = "COMPLETE"  # the task changes after the answers were given
    assert got.tasks[0].sub_tasks[0].state == "WAITTING"
    assert action.actions[0].state == "WAITTING"
    # the REST form of the answer is the robot API's document: nested tasks untagged
    doc = as_document(got.tasks[0])
    assert "type" not in doc["sub_tasks"][1] and doc["sub_tasks"][0]["type"] == "sleep_action"
    assert msgspec.json.decode(msgspec.json.encode(got.tasks[0]), type=Task) == got.tasks[0]


def test_update_and_create_action_take_the_typed_requests(manager: TaskManager) -> None:
    task = manager.create({"name": "a", "sub_tasks": [{"type": "sleep_action",
                                                        "wait_time": 1}]})
    upd = call(manager, "update", tm.task_request("update", task.id, {"name": "b"}))
    assert isinstance(upd, tm.TaskResponse) and upd.task is not None
    assert upd.task.name == "b" and upd.task.sub_tasks == task.sub_tasks
    added = call(manager, "create_action", tm.task_request(
        "create_action", body={"type": "tts_action", "text": "hi", "task_id": task.id}))
    assert isinstance(added, tm.TaskResponse) and added.task is not None
    assert len(added.task.sub_tasks) == 2 and added.task.sub_tasks[1].id
    bad = call(manager, "create_action", tm.task_request(
        "create_action", body={"type": "nav_action", "x": 1}))
    assert bad.code == ResultCode.INVALID and "x and y" in bad.message  # type: ignore[attr-defined]
