"""A launch's own services (docs/launch.md, "Restart and shutdown"): ``/launch/restart``
stops every process in order and starts them again (new PIDs, back in the graph) while the
launch goes on; ``/launch/shutdown`` stops it cleanly (exit code 0) and runs the operator's
``--on-shutdown`` command after; a restart asked twice at once is refused with the reason."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from zenros.msgs.std_srvs import Trigger, TriggerRequest
from zenros.node import Node
from zenros.testing import wait_for

pytestmark = [pytest.mark.system, pytest.mark.timeout(120)]

LAUNCH = """
nodes:
  - module: zenros.examples.talker
    name: chatty
    params: [{rate: 20.0}]
  - module: zenros.examples.listener
"""


def pids(node: Node) -> dict[str, int]:
    return {n.name: n.pid for n in node.context.graph.nodes()
            if n.name in ("/chatty", "/listener")}


def test_restart_starts_every_process_again(launch_text: Any) -> None:
    with launch_text(LAUNCH) as (proc, ctx):
        assert proc.wait_line("listener is ready", 30), proc.output
        user = Node("user", context=ctx)
        try:
            assert ctx.graph.wait_for(lambda: len(pids(user)) == 2, 20)
            before = pids(user)
            restart = user.create_client(Trigger, "/launch/restart")
            assert restart.wait_for_service(20), proc.output
            res = restart.call(TriggerRequest(), timeout=10)
            assert res.success and res.message == "restarting the launch's 2 processes", res
            again = restart.call(TriggerRequest(), timeout=10)
            assert not again.success and again.message == "a restart is under way", again
            assert ctx.graph.wait_for(
                lambda: len(pids(user)) == 2 and not set(pids(user).values())
                & set(before.values()), 60), (before, pids(user), proc.output)
            assert proc.wait_line("restarted 2 processes", 30), proc.output
            assert proc.popen.poll() is None  # the launch goes on
            # and it can be restarted again once the first is done
            assert restart.call(TriggerRequest(), timeout=10).success
            assert wait_for(lambda: proc.output.count("restarted 2 processes") == 2, 60), \
                proc.output
        finally:
            user.close()


def test_shutdown_stops_the_launch_and_runs_the_operators_command(
        launch_text: Any, tmp_path: Path) -> None:
    mark = tmp_path / "powered-off"
    cmd = f"touch {mark}"
    with launch_text(LAUNCH, "--on-shutdown", cmd) as (proc, ctx):
        assert proc.wait_line("listener is ready", 30), proc.output
        user = Node("user", context=ctx)
        try:
            shutdown = user.create_client(Trigger, "/launch/shutdown")
            assert shutdown.wait_for_service(20), proc.output
            res = shutdown.call(TriggerRequest(), timeout=10)
            assert res.success and res.message == "stopping the launch's 2 processes", res
        finally:
            user.close()
        assert proc.wait(60) == 0, proc.output
        assert "shutdown requested" in proc.output
        assert f"running the shutdown command: touch {mark}" in proc.output
        assert mark.exists()


def test_bad_control_flags_are_usage_errors(tmp_path: Path) -> None:
    (tmp_path / "l.yaml").write_text(LAUNCH)
    for flags, words in ((["--control", "no spaces"], "--control 'no spaces'"),
                         (["--on-shutdown", "echo 'open"], "--on-shutdown")):
        out = subprocess.run([sys.executable, "-m", "zenros.cli", "launch",
                              str(tmp_path / "l.yaml"), *flags],
                             check=False, capture_output=True, text=True, timeout=60)
        assert out.returncode == 2 and words in out.stderr, out.stderr


def test_the_robot_api_restarts_and_shuts_down_its_launch(launch_text: Any,
                                                           tmp_path: Path) -> None:
    """docs/robot-api.md §3.3 with curl's view: GET /system/restart_robot restarts every
    process, the gateway answering it too; GET /system/shutdown ends the launch cleanly."""
    import httpx
    from zenros.testing import free_port

    port = free_port()
    text = LAUNCH + f"""
  - module: zenros.services.gateway
    params: [{{rest_port: {port}, ws_port: 0, modbus_port: 0, rosbridge_port: -1,
               discovery_port: -1, no_token_check: true,
               data_dir: "{tmp_path / 'gw'}", fs_root: "{tmp_path}"}}]
"""
    base = f"http://127.0.0.1:{port}/api/v1"

    def get(path: str) -> httpx.Response | None:
        try:
            return httpx.get(base + path, timeout=10)
        except httpx.HTTPError:
            return None

    with launch_text(text) as (proc, ctx):
        assert proc.wait_line("gateway is ready", 60), proc.output
        user = Node("user", context=ctx)
        try:
            assert ctx.graph.wait_for(lambda: len(pids(user)) == 2, 20)
            before = pids(user)
            assert ctx.graph.wait_for_service("/launch/restart", 20)
            r = get("/system/restart_robot")
            assert r is not None and r.status_code == 200 and r.json() == {"result": True}, r
            assert ctx.graph.wait_for(
                lambda: len(pids(user)) == 2 and not set(pids(user).values())
                & set(before.values()), 60), (before, pids(user), proc.output)
            assert proc.wait_line("restarted 3 processes", 60), proc.output
            assert wait_for(lambda: (r := get("/system/info")) is not None
                            and r.status_code == 200, 60), proc.output
            r = get("/system/shutdown")
            assert r is not None and r.json() == {"result": True}, r
        finally:
            user.close()
        assert proc.wait(60) == 0, proc.output
