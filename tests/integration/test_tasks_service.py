"""The tasks service over Zenoh: every call, its refusals with codes, tasks/status, smach."""

from __future__ import annotations

import json
import logging
import signal
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from zenros.context import Context
from zenros.msgs.zenros_msgs.tasks import TaskCall, TaskCallRequest, TaskStatus
from zenros.node import Node
from zenros.rpc import Client
from zenros.services.tasks.node import TasksNode
from zenros.smach.introspection import StateStructure
from zenros.testing import Collector, Proc, free_port, loopback_options, unique_prefix, wait_for


@pytest.fixture
def tasks(ctx_pair: list[Context], tmp_path: Path) -> Iterator[TasksNode]:
    node = TasksNode(context=ctx_pair[0], parameter_overrides={"data_dir": str(tmp_path)})
    yield node
    node.close()


class Api:
    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx
        self.clients: dict[str, Client] = {}

    def __call__(self, name: str, id: str = "", body: Any = None) -> tuple[int, Any, str]:
        if name not in self.clients:
            self.clients[name] = Client(self.ctx, TaskCall, f"/tasks/{name}")
            assert self.clients[name].wait_for_service(10)
        text = body if isinstance(body, str) else json.dumps(body) if body is not None else ""
        r = self.clients[name].call(TaskCallRequest(id=id, body=text), timeout=10)
        return r.code, json.loads(r.body) if r.body else None, r.message


@pytest.fixture
def api(ctx_pair: list[Context], tasks: TasksNode) -> Api:
    return Api(ctx_pair[1])


def test_create_start_complete_and_status(api: Api, make_node: Any) -> None:
    watcher: Node = make_node("watch", side=1)
    got = Collector()
    watcher.create_subscription(TaskStatus, "/tasks/status", got)
    code, task, _ = api("create", body={"name": "hello", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 0.05}, {"type": "tts_action", "text": "hi"}]})
    assert code == 200 and task["state"] == "WAITTING"
    code, started, _ = api("start", task["id"])
    assert code == 200 and started["state"] == "WORKING"
    assert wait_for(lambda: any(m.state == "COMPLETE" and m.id == task["id"]
                                for m in got.items), 10)
    final = next(m for m in got.items if m.state == "COMPLETE")
    assert final.progress == 1.0 and json.loads(final.task)["sub_tasks"][1]["state"] == "COMPLETE"
    states = [m.state for m in got.items if m.id == task["id"]]
    assert states[0] in ("WAITTING", "WORKING") and "WORKING" in states
    code, listed, _ = api("get")
    assert [t["id"] for t in listed] == [task["id"]]


@pytest.mark.parametrize("name, id, body, code, words", [
    ("create", "", {"sub_tasks": [{"type": "fly"}]}, 400, "unknown action type 'fly'"),
    ("create", "", "{not json", 400, "not valid JSON"),
    ("create", "", "[" * 5000, 400, "not valid JSON"),
    ("create", "", [1, 2], 400, "JSON object"),
    ("start", "no-such-id", None, 404, "no task with id 'no-such-id'"),
    ("start", "", None, 400, "'id'"),
    ("get_action", "nope", None, 404, "no action"),
    ("loop", "x", {"loop_flag": "yes"}, 400, "loop_flag"),
    ("stop", "", None, 409, "no task is running"),
])
def test_refusals_have_codes(api: Api, name: str, id: str, body: Any, code: int,
                             words: str) -> None:
    got, _, message = api(name, id, body)
    assert got == code and words in message
    assert api("get")[0] == 200  # and the service still answers


def test_running_task_is_a_live_state_machine(api: Api, make_node: Any) -> None:
    code, task, _ = api("create", body={"sub_tasks": [{"type": "wait_req_action"}]})
    watcher: Node = make_node("watch2", side=1)
    structure = Collector()
    watcher.create_subscription(StateStructure, "/tasks/smach/structure", structure)
    api("start", task["id"])
    assert wait_for(lambda: any([c.label for c in s.children] == ["00_WAIT_REQ_ACTION"]
                                and s.type == "TaskMachine" for s in structure.items), 10), \
        structure.items
    code, paused, _ = api("pause", task["id"])
    assert code == 200 and paused["state"] == "PAUSED"
    assert paused["sub_tasks"][0]["state"] == "PAUSED"
    code, _, msg = api("pause", task["id"])
    assert code == 409 and "PAUSED" in msg
    api("resume", task["id"])
    assert api("update_wait_req")[0] == 200
    assert wait_for(lambda: api("get", task["id"])[1]["state"] == "COMPLETE", 10)
    # the next run is shown by the same server
    code, second, _ = api("create", body={"sub_tasks": [
        {"type": "sleep_action", "wait_time": 0}, {"type": "tts_action", "text": "x"}]})
    api("start", second["id"])
    assert wait_for(lambda: any([c.label for c in s.children]
                                == ["00_SLEEP_ACTION", "01_TTS_ACTION"]
                                for s in structure.items), 10)


NAV_STANDIN = """
import sys, threading
from zenros.action import ActionServer
from zenros.context import Context
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseResult
from zenros.node import Node
from zenros.testing import loopback_options

port, prefix, finish = int(sys.argv[1]), sys.argv[2], sys.argv[3] == "finish"

def say(line):
    # one write per line: a goal can arrive (on a Zenoh thread) while "serving" is printed,
    # and print() writes its arguments and the newline one by one
    sys.stdout.write(line + "\\n")
    sys.stdout.flush()

def execute(handle):
    say(f"goal {handle.request.pose.pose.position.x}")
    while not (finish or handle.is_cancel_requested):
        threading.Event().wait(0.01)
    if handle.is_cancel_requested:
        handle.canceled()
    else:
        handle.succeed()
    return NavigateToPoseResult()

node = Node("nav", context=Context(loopback_options(connect=[port]), prefix=prefix))
ActionServer(node, NavigateToPose, "navigate_to_pose", execute)
say("serving")
sys.stdin.readline()
"""


def test_nav_goal_outlives_its_server_going_away(tmp_path: Path, procs: list[Proc],
                                                 caplog: pytest.LogCaptureFixture) -> None:
    """navigate_to_pose's server killed mid-goal (as a link cut or a crash looks): the task
    waits for it, sends the goal again when a server is back, and completes; no ERROR."""
    port, prefix = free_port(), unique_prefix()
    script = tmp_path / "nav_standin.py"
    script.write_text(NAV_STANDIN)
    caplog.set_level(logging.WARNING)
    with Context(loopback_options(port), prefix=prefix) as ctx:
        tasks = TasksNode(context=ctx, parameter_overrides={"data_dir": str(tmp_path)})
        try:
            api = Api(ctx)
            first = Proc([sys.executable, str(script), str(port), prefix, "hold"])
            procs.append(first)
            assert first.wait_line("serving", 15), first.output
            _, task, _ = api("create", body={"sub_tasks": [{"type": "nav_action", "x": 3.0,
                                                            "y": 1.0}]})
            api("start", task["id"])
            assert first.wait_line("goal 3.0", 15), first.output
            first.signal(signal.SIGKILL)
            assert wait_for(lambda: "sending the goal again" in caplog.text, 15)
            assert api("get", task["id"])[1]["state"] == "WORKING"
            second = Proc([sys.executable, str(script), str(port), prefix, "finish"])
            procs.append(second)
            assert second.wait_line("goal 3.0", 20), second.output
            assert wait_for(lambda: api("get", task["id"])[1]["state"] != "WORKING", 15)
            done = api("get", task["id"])[1]
            assert done["state"] == "COMPLETE", done
        finally:
            tasks.close()
