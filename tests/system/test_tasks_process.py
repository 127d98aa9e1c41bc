"""The tasks service as a process: kill -9 mid-task loses nothing; the CLI drives it."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import pytest
from zenros.context import Context
from zenros.msgs.zenros_msgs import ResultCode
from zenros.msgs.zenros_msgs.tasks import TASK_SERVICES, response_data, task_request
from zenros.rpc import Client
from zenros.testing import Proc, wait_for

pytestmark = pytest.mark.system


def start_tasks(router: str, prefix: str, home: Path) -> Proc:
    proc = Proc([sys.executable, "-m", "zenros.services.tasks", "-e", router, "--prefix",
                 prefix], env={"ZENROS_HOME": str(home)})
    assert proc.wait_line("started", 15), proc.output
    return proc


def call(ctx: Context, name: str, id: str = "", body: object = None) -> dict:
    client = Client(ctx, TASK_SERVICES[name], f"/tasks/{name}")
    assert client.wait_for_service(10)
    r = client.call(task_request(name, id, body), timeout=10)
    assert r.code == ResultCode.OK, r.message
    return response_data(r, single=bool(id))


def cli(router: str, prefix: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", "task", *args, "-e", router,
                           "--prefix", prefix], capture_output=True, text=True, timeout=60,
                          check=False)


def test_kill_9_mid_task_loses_nothing(router: str, prefix: str, tmp_path: Path,
                                       observer: Context, procs: list[Proc]) -> None:
    procs.append(tasks := start_tasks(router, prefix, tmp_path))
    ids = [call(observer, "create", body={"name": f"t{i}", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 0.01}]})["id"] for i in range(5)]
    long = call(observer, "create", body={"name": "long", "sub_tasks": [
        {"type": "sleep_action", "wait_time": 0}, {"type": "wait_req_action"},
        {"type": "sleep_action", "wait_time": 0}]})
    call(observer, "start", long["id"])
    assert wait_for(lambda: call(observer, "get", long["id"])["sub_tasks"][1]["state"]
                    == "WORKING", 10)
    tasks.signal(signal.SIGKILL)
    assert tasks.wait(10) == -signal.SIGKILL

    procs.append(start_tasks(router, prefix, tmp_path))
    assert observer.graph.wait_for(lambda: len(observer.graph.servers("/tasks/get")) == 1, 10)
    back = call(observer, "get", long["id"])
    assert back["state"] == "PAUSED"
    assert [a["state"] for a in back["sub_tasks"]] == ["COMPLETE", "PAUSED", "WAITTING"]
    assert back["progress"] == pytest.approx(1 / 3, abs=0.01)
    assert {t["id"] for t in call(observer, "get")} == {*ids, long["id"]}

    out = cli(router, prefix, "list")
    assert out.returncode == 0 and "PAUSED" in out.stdout and "long" in out.stdout, out
    out = cli(router, prefix, "resume", long["id"])
    assert out.returncode == 0, out.stderr
    call(observer, "update_wait_req")
    assert wait_for(lambda: call(observer, "get", long["id"])["state"] == "COMPLETE", 10)
    out = cli(router, prefix, "start", "nope")
    assert out.returncode == 1 and "no task with id 'nope'" in out.stderr


def test_cli_create_with_start_starts_the_task(router: str, prefix: str, tmp_path: Path,
                                               observer: Context, procs: list[Proc]) -> None:
    """``zenros task create ... --start``: the README's task runs, not waits (issue 37.8)."""
    import json

    procs.append(start_tasks(router, prefix, tmp_path))
    out = cli(router, prefix, "create", "{name: demo, sub_tasks: [{type: wait_req_action}]}",
              "--start", "--json")
    assert out.returncode == 0, out.stderr
    task = json.loads(out.stdout)
    assert task["name"] == "demo" and task["state"] in ("WORKING", "COMPLETE"), task
    assert wait_for(lambda: call(observer, "get", task["id"])["state"] == "WORKING", 10)
    call(observer, "update_wait_req")
    assert wait_for(lambda: call(observer, "get", task["id"])["state"] == "COMPLETE", 10)
    out = cli(router, prefix, "create", "{name: later, sub_tasks: []}", "--json")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["state"] == "WAITTING"  # without --start it waits
