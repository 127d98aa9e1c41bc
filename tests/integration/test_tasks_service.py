"""The tasks service over Zenoh: every call, its refusals with codes, tasks/status, smach.

The calls are typed (zenros_msgs.tasks); `Api` builds them from the robot API's plain data
and answers (ResultCode, the document as plain data, the refusal's message)."""

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
from zenros.msgs.zenros_msgs import ResultCode
from zenros.msgs.zenros_msgs.tasks import (
    TASK_SERVICES,
    TaskStatus,
    response_data,
    task_request,
)
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

    def __call__(self, name: str, id: str = "", body: Any = None
                 ) -> tuple[ResultCode, Any, str]:
        if name not in self.clients:
            self.clients[name] = Client(self.ctx, TASK_SERVICES[name], f"/tasks/{name}")
            assert self.clients[name].wait_for_service(10)
        r = self.clients[name].call(task_request(name, id, body), timeout=10)
        return r.code, response_data(r, single=bool(id)), r.message


@pytest.fixture
def api(ctx_pair: list[Context], tasks: TasksNode) -> Api:
    return Api(ctx_pair[1])


def test_create_start_complete_and_status(api: Api, make_node: Any) -> None:
    watcher: Node = make_node("watch", side=1)
    got = Collector()
    watcher.create_subscription(TaskStatus, "/tasks/status", got)
    code, task, _ = api("create", body={"name": "hello", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 0.05}, {"type": "tts_action", "text": "hi"}]})
    assert code == ResultCode.OK and task["state"] == "WAITTING"
    code, started, _ = api("start", task["id"])
    assert code == ResultCode.OK and started["state"] == "WORKING"
    assert wait_for(lambda: any(m.state == "COMPLETE" and m.id == task["id"]
                                for m in got.items), 10)
    final = next(m for m in got.items if m.state == "COMPLETE")
    assert final.progress == 1.0 and final.task.sub_tasks[1].state == "COMPLETE"
    states = [m.state for m in got.items if m.id == task["id"]]
    assert states[0] in ("WAITTING", "WORKING") and "WORKING" in states
    code, listed, _ = api("get")
    assert [t["id"] for t in listed] == [task["id"]]


@pytest.mark.parametrize("name, id, body, code, words", [
    ("create", "", {"sub_tasks": [{"type": "sleep_action", "wait_time": 1}],
                    "control_type": "fly"}, ResultCode.INVALID, "unknown control_type 'fly'"),
    ("start", "no-such-id", None, ResultCode.NOT_FOUND, "no task with id 'no-such-id'"),
    ("start", "", None, ResultCode.INVALID, "'id'"),
    ("get_action", "nope", None, ResultCode.NOT_FOUND, "no action"),
    ("stop", "", None, ResultCode.CONFLICT, "no task is running"),
])
def test_refusals_have_codes(api: Api, name: str, id: str, body: Any, code: ResultCode,
                             words: str) -> None:
    got, _, message = api(name, id, body)
    assert got == code and words in message
    assert api("get")[0] == ResultCode.OK  # and the service still answers


@pytest.mark.parametrize("name, payload, words", [
    ("create", b'{"task": {"sub_tasks": [{"type": "fly"}]}}', "Invalid value 'fly'"),
    ("create", b"{not json", "BadRequest"),
    ("create", b"[" * 5000, "BadRequest"),
    ("create", b"[1, 2]", "BadRequest"),
    ("loop", b'{"id": "x", "loop_flag": "yes"}', "loop_flag"),
])
def test_malformed_requests_are_refused(ctx_pair: list[Context], api: Api, name: str,
                                        payload: bytes, words: str) -> None:
    """What is not a typed request (bad JSON, a wrong shape, an unknown action type, a
    mistyped field) is refused before the manager sees it, and the service goes on."""
    api("get")  # the service is up
    key = ctx_pair[1].keys.service(f"/tasks/{name}")
    replies = list(ctx_pair[1].session.get(key, payload=payload, timeout=5.0))
    assert len(replies) == 1 and replies[0].err is not None
    body = json.loads(replies[0].err.payload.to_bytes())
    assert body["error"] == "BadRequest" and words in f"{body['error']}: {body['message']}"
    assert api("get")[0] == ResultCode.OK


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
    assert code == ResultCode.OK and paused["state"] == "PAUSED"
    assert paused["sub_tasks"][0]["state"] == "PAUSED"
    code, _, msg = api("pause", task["id"])
    assert code == ResultCode.CONFLICT and "PAUSED" in msg
    api("resume", task["id"])
    assert api("update_wait_req")[0] == ResultCode.OK
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
