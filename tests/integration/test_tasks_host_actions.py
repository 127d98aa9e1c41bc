"""The task actions that change the robot's host (docs/tasks.md), through a real tasks service:
``change_setting_action`` changes the gateway's ``/system/config`` (over its
``system/set_config``) and sets ``init_settings`` back when the task ends; ``roslaunch_action``
starts a launch file as a child ``zenros launch`` and stops it, with every process it started,
when the task ends or the service stops. Bad parameters of every new type are a 400 naming
the field through the gateway's POST /action and POST /task."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from task_runs import run_task
from zenros.context import Context
from zenros.msgs.zenros_msgs import ResultCode
from zenros.msgs.zenros_msgs.tasks import TASK_SERVICES, response_data, task_request
from zenros.node import Node
from zenros.services.gateway.node import GatewayNode
from zenros.services.tasks.node import TasksNode
from zenros.testing import wait_for

ENDED = ("COMPLETE", "ERROR", "FAILED", "CANCELLED")


def run(http: httpx.Client, *actions: dict[str, Any], timeout: float = 30) -> dict[str, Any]:
    return run_task(http, *actions, name="host", timeout=timeout)


def speed(http: httpx.Client) -> float:
    return float(http.get("/system/config").json()["navigation_speed"])


def test_change_setting_sets_the_config_and_the_tasks_end_sets_it_back(
        tasks: TasksNode, gw: GatewayNode, http: httpx.Client) -> None:
    assert speed(http) == 0.5
    r = http.post("/task", json={"name": "slow", "sub_tasks": [
        {"type": "change_setting_action", "settings": {"navigation_speed": 0.2},
         "init_settings": {"navigation_speed": 0.5}},
        {"type": "wait_req_action"}]})
    task_id = r.json()["id"]
    assert http.get("/task/start", params={"id": task_id}).status_code == 200
    assert wait_for(lambda: speed(http) == 0.2, 20)
    first = http.get("/task", params={"id": task_id}).json()["sub_tasks"][0]
    assert first["state"] == "COMPLETE" and "navigation_speed=0.2" in first["result"], first
    assert http.get("/action/update_wait_req").status_code == 200
    assert wait_for(lambda: http.get("/task", params={"id": task_id}).json()["state"]
                    == "COMPLETE", 20)
    assert wait_for(lambda: speed(http) == 0.5, 10)
    # without init_settings the change stays
    done = run(http, {"type": "change_setting_action", "settings": {"auto_charge": True}})
    assert done["state"] == "COMPLETE", done
    assert http.get("/system/config").json()["auto_charge"] is True


@pytest.mark.parametrize(("settings", "init", "words"), [
    ({"warp_speed": 9}, None, "unknown configuration key 'warp_speed'"),
    ({"navigation_speed": 99}, None, "navigation_speed"),
    ({"navigation_speed": 0.3}, {"warp": 1}, "init_settings: unknown configuration key 'warp'"),
])
def test_a_bad_setting_is_an_error_naming_the_key(
        tasks: TasksNode, gw: GatewayNode, http: httpx.Client, settings: dict[str, Any],
        init: dict[str, Any] | None, words: str) -> None:
    action: dict[str, Any] = {"type": "change_setting_action", "settings": settings}
    if init is not None:
        action["init_settings"] = init
    done = run(http, action)
    assert done["state"] == "ERROR" and words in done["sub_tasks"][0]["result"], done
    assert speed(http) == 0.5  # nothing changed


@pytest.mark.parametrize(("action", "field"), [
    ({"type": "elevator_req_action"}, "level"),
    ({"type": "elevator_req_action", "level": 2, "direction": "sideways"}, "direction"),
    ({"type": "elevator_req_action", "level": "two"}, "level"),
    ({"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 2, "cmd": "jump"}, "cmd"),
    ({"type": "lbt_elevator_req_action", "from_level": 2, "to_level": 2, "cmd": "enter"},
     "to_level"),
    ({"type": "lbt_elevator_ack_action", "level": 2}, "level"),
    ({"type": "none_stop_nav_action", "x": 1.0, "y": 2.0, "radius": -1}, "radius"),
    ({"type": "none_stop_nav_action", "x": 1.0}, "y"),
    ({"type": "change_setting_action", "settings": {}}, "settings"),
    ({"type": "change_setting_action", "settings": [1]}, "settings"),
    ({"type": "change_setting_action", "settings": {"a": 1}, "init_settings": 3},
     "init_settings"),
    ({"type": "roslaunch_action", "launch_cmd": "roslaunch pkg /etc/passwd.launch"},
     "launch_cmd"),
    ({"type": "roslaunch_action", "launch_cmd": "sim.yaml; rm -rf /"}, "launch_cmd"),
    ({"type": "roslaunch_action"}, "launch_cmd"),
    ({"type": "audio_record_action", "duration": 0}, "duration"),
    ({"type": "audio_record_action", "filename": "x" * 200}, "filename"),
])
def test_bad_parameters_are_a_400_naming_the_field(
        tasks: TasksNode, gw: GatewayNode, http: httpx.Client, action: dict[str, Any],
        field: str) -> None:
    r = http.post("/action", json=action)
    assert r.status_code == 400 and field in r.json()["description"], r.text
    r = http.post("/task", json={"name": "bad", "sub_tasks": [action]})
    assert r.status_code == 400 and field in r.json()["description"], r.text


# ---------------------------------------------------------------------- roslaunch_action

TALK = """# One talker, for roslaunch_action's test.
args:
  rate: {default: "2.0", type: float}
nodes:
  - module: zenros.examples.talker
    name: talker
    params: {rate: $(arg rate)}
"""


class Tasks:
    """A tasks service on the router (its launches join the same graph) and its calls."""

    def __init__(self, node: TasksNode, user: Node) -> None:
        self.node, self.user = node, user
        self.clients: dict[str, Any] = {}

    def call(self, name: str, id: str = "", body: Any = None) -> Any:
        if name not in self.clients:
            self.clients[name] = self.user.create_client(TASK_SERVICES[name], f"/tasks/{name}")
            assert self.clients[name].wait_for_service(10)
        r = self.clients[name].call(task_request(name, id, body), timeout=20)
        assert r.code == ResultCode.OK, r.message
        return response_data(r, single=bool(id))

    def state(self, task_id: str) -> dict[str, Any]:
        out: dict[str, Any] = self.call("get", task_id)
        return out


@pytest.fixture
def launching(observer: Context, router: str, tmp_path: Path,
              monkeypatch: pytest.MonkeyPatch) -> Iterator[Tasks]:
    (tmp_path / "launch").mkdir()
    (tmp_path / "launch" / "talk.yaml").write_text(TALK)
    monkeypatch.setenv("ZENROS_CONNECT", router)  # the launches' processes meet us there
    node = TasksNode(context=observer, parameter_overrides={
        "data_dir": str(tmp_path / "t"), "launch_dir": str(tmp_path / "launch")})
    user = Node("user", context=observer)
    try:
        yield Tasks(node, user)
    finally:
        user.close()
        node.close()
        for pid in node.link.launcher.running().values() if node.link.launcher else []:
            _kill_tree(pid)  # only when a test failed half way: the node's close stopped them


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[-1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _children(pid: int) -> list[int]:
    out = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[-1].split()
            except OSError:
                continue
            if fields[1] == str(pid):
                out.append(int(entry.name))
    return out


def _kill_tree(pid: int) -> None:
    import os
    import signal
    for p in [*_children(pid), pid]:
        try:
            os.killpg(p, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass


def _started(t: Tasks, launch_cmd: str) -> tuple[str, int, list[int]]:
    """A task of ``launch_cmd`` then a wait, started; (its id, the launch's pid, its
    processes') once the launch's action is done."""
    task = t.call("create", body={"name": "launch", "sub_tasks": [
        {"type": "roslaunch_action", "launch_cmd": launch_cmd}, {"type": "wait_req_action"}]})
    t.call("start", task["id"])
    seen: list[dict[str, Any]] = []

    def launched() -> bool:
        seen.append(t.state(task["id"])["sub_tasks"][0])
        return seen[-1]["state"] not in ("WAITTING", "WORKING")
    assert wait_for(launched, 90), seen[-1:]
    first = seen[-1]
    assert first["state"] == "COMPLETE", first
    assert t.node.link.launcher is not None
    (pid,) = t.node.link.launcher.running().values()
    return task["id"], pid, _children(pid)


def test_roslaunch_runs_a_launch_file_until_the_task_ends(launching: Tasks,
                                                           observer: Context) -> None:
    t = launching
    task_id, pid, children = _started(t, "roslaunch zenros talk.launch rate:=5")
    assert "/talker" in observer.graph.node_names()
    assert children and all(_alive(p) for p in children)
    result = t.state(task_id)["sub_tasks"][0]["result"]
    assert "talk.yaml rate:=5 started" in result and "/talker up" in result, result
    t.call("update_wait_req")
    assert wait_for(lambda: t.state(task_id)["state"] == "COMPLETE", 20)
    assert wait_for(lambda: not any(_alive(p) for p in [pid, *children]), 30)
    assert wait_for(lambda: "/talker" not in observer.graph.node_names(), 10)


def test_stopping_the_tasks_service_stops_its_launches(launching: Tasks) -> None:
    t = launching
    _, pid, children = _started(t, "talk.yaml")
    t.node.close()
    assert not any(_alive(p) for p in [pid, *children])


def test_a_launch_file_not_shipped_or_a_bad_argument_is_an_error(launching: Tasks) -> None:
    t = launching
    for cmd, words in (("roslaunch xiaoqiang_track xiaoqiang_track.launch",
                        "no launch file 'xiaoqiang_track': the launch files are talk"),
                       ("talk.yaml nonsense:=1", "nonsense")):
        task = t.call("create", body={"sub_tasks": [{"type": "roslaunch_action",
                                                     "launch_cmd": cmd}]})
        t.call("start", task["id"])
        assert wait_for(lambda task=task: t.state(task["id"])["state"] in ENDED, 20)
        done = t.state(task["id"])
        assert done["state"] == "ERROR" and words in done["sub_tasks"][0]["result"], done
    assert t.node.link.launcher is not None and t.node.link.launcher.running() == {}
