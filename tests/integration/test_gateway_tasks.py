"""REST /task and /action against the real tasks service, through the gateway (docs/robot-api.md
§8-§9)."""

from __future__ import annotations

import httpx
from zenros.services.gateway.node import GatewayNode
from zenros.services.tasks.node import TasksNode
from zenros.testing import wait_for


def test_without_tasks_service_503(http: httpx.Client) -> None:
    r = http.get("/task")
    assert r.status_code == 503 and "tasks service is starting" in r.json()["description"]
    assert r.headers["retry-after"] == "2"  # never seen yet, right after the gateway started


def test_task_lifecycle_and_actions(http: httpx.Client, tasks: TasksNode) -> None:
    r = http.post("/task", json={"name": "t", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 0.05}]})
    assert r.status_code == 200, r.text
    task = r.json()
    assert task["state"] == "WAITTING" and task["name"] == "t"
    assert any(t["id"] == task["id"] for t in http.get("/task").json())
    assert http.get("/task/start", params={"id": task["id"]}).status_code == 200
    assert wait_for(lambda: http.get("/task", params={"id": task["id"]}).json()["state"]
                    == "COMPLETE", 10)
    r = http.get("/task/loop", params={"id": task["id"], "loop_flag": "true"})
    assert r.status_code == 200 and r.json()["loop_flag"] is True
    # actions: POST wraps one in an "auto task"
    r = http.post("/action", json={"type": "sleep_action", "wait_time": 2})
    assert r.status_code == 200, r.text
    auto = r.json()
    assert auto["name"] == "auto task" and auto["sub_tasks"][0]["type"] == "sleep_action"
    action_id = auto["sub_tasks"][0]["id"]
    assert http.get("/action", params={"id": action_id}).json()["wait_time"] == 2
    assert http.get("/action/update_wait_req").json() == {"status": "ok"}
    assert http.delete("/task", params={"id": auto["id"]}).json() == {"status": "ok"}
    # the tasks service's refusals pass through with their codes
    r = http.get("/task/start", params={"id": "nope"})
    assert r.status_code == 404 and r.json()["status"] == "error"
    assert http.post("/action", json={"wait_time": 1}).status_code == 400
    assert http.get("/task/start").status_code == 400            # id required
    assert http.get("/task/loop", params={"id": "x", "loop_flag": "maybe"}).status_code == 400
    r = http.post("/task", json={"name": "bad", "sub_tasks": [{"type": "warp_action"}]})
    assert r.status_code == 400, r.text


def test_action_types_through_the_api(http: httpx.Client, tasks: TasksNode,
                                      gw: GatewayNode) -> None:
    """§0 rows 22-25: wait_req_action released by /action/update_wait_req, a callback_action
    calling back into the gateway, a tts_action, a sequence control_type; progress counts."""
    callback = f"http://127.0.0.1:{gw.rest_port}/api/v1/system/status"
    r = http.post("/task", json={"name": "kinds", "control_type": "sequence", "sub_tasks": [
        {"type": "wait_req_action"},
        {"type": "callback_action", "url": callback, "method": "GET"},
        {"type": "tts_action", "text": "done"}]})
    assert r.status_code == 200, r.text
    task = r.json()
    assert task["state"] == "WAITTING" and task["progress"] == 0
    assert http.get("/task/start", params={"id": task["id"]}).json()["state"] == "WORKING"

    def doc() -> dict[str, object]:
        return dict(http.get("/task", params={"id": task["id"]}).json())

    assert wait_for(lambda: doc()["current_task"] is not None
                    and doc()["current_task"]["type"] == "wait_req_action", 5)  # type: ignore[index]
    assert http.get("/action/update_wait_req").json() == {"status": "ok"}
    assert wait_for(lambda: doc()["state"] == "COMPLETE", 10), doc()
    final = doc()
    assert final["progress"] == 1.0
    assert [a["state"] for a in final["sub_tasks"]] == ["COMPLETE"] * 3  # type: ignore[attr-defined]
