"""`zenros launch` with Zenoh: its own router, readiness from liveliness, respawn into the
graph, and a clean Ctrl-C."""

from __future__ import annotations

import os
import re
import signal
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from zenros.context import Context
from zenros.testing import Proc, free_port, unique_prefix

pytestmark = pytest.mark.system

LAUNCH = """
nodes:
  - module: zenros.examples.talker
    name: chatty
    respawn: true
    params: [{rate: 20.0}]
  - module: zenros.examples.listener
"""


@pytest.fixture
def launched(launch_text: Any) -> Iterator[tuple[Proc, Context]]:
    with launch_text(LAUNCH) as rig:
        yield rig


def test_launch_starts_router_and_nodes_and_reports_ready(launched: tuple[Proc, Context]) -> None:
    proc, ctx = launched
    assert proc.wait_line("chatty is ready", 20), proc.output
    assert proc.wait_line("listener is ready", 20), proc.output
    assert ctx.graph.wait_for(lambda: {"/chatty", "/listener"} <= set(ctx.graph.node_names()), 10)
    assert proc.wait_line("[listener]", 10)  # prefixed output of the node


def test_killed_respawnable_node_is_started_again_and_back_in_the_graph(
    launched: tuple[Proc, Context]
) -> None:
    """The supervisor restarts it (its reaction time is test_launch_supervisor's), and the
    new process, not the killed one, is the node in the graph. How long kill to graph takes
    is a speed, measured beside a bare zenoh-python process's start by bench/respawn.py
    (docs/launch.md); here it is bounded only to fail rather than hang."""
    proc, ctx = launched
    g = ctx.graph
    assert g.wait_for(lambda: any(n.name == "/chatty" for n in g.nodes()), 20)
    old = next(n for n in g.nodes() if n.name == "/chatty")
    os.kill(old.pid, signal.SIGKILL)
    assert g.wait_for(
        lambda: any(n.name == "/chatty" and n.pid != old.pid for n in g.nodes()), 30
    ), proc.output
    new = next(n for n in g.nodes() if n.name == "/chatty")
    assert f"started chatty (pid {new.pid})" in proc.output, proc.output
    assert g.wait_for(lambda: old.pid not in {n.pid for n in g.nodes()}, 10)


def test_ctrl_c_stops_everything_cleanly(launched: tuple[Proc, Context]) -> None:
    proc, ctx = launched
    assert proc.wait_line("listener is ready", 20), proc.output
    proc.signal(signal.SIGINT)
    assert proc.wait(30) == 0, proc.output
    assert "launch finished with exit code 0" in proc.output
    g = ctx.graph
    assert g.wait_for(lambda: not ({"/chatty", "/listener"} & set(g.node_names())), 5)


def test_a_node_that_fails_at_once_ends_the_launch_without_waiting_for_readiness(
    tmp_path: Path,
) -> None:
    """The readiness wait (20 s at most) is cancelled when the process has ended."""
    (tmp_path / "fail.yaml").write_text("nodes:\n  - module: zenros.examples.no_such_node\n")
    proc = Proc([sys.executable, "-m", "zenros.cli", "launch", str(tmp_path / "fail.yaml"),
                 "--data-dir", str(tmp_path / "home")],
                env={"ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}",
                     "ZENROS_PREFIX": unique_prefix()})
    try:
        assert proc.wait_line("launch finished with exit code 1", 20), proc.output
        finished = time.monotonic()
        assert proc.wait(10) == 1, proc.output
        assert time.monotonic() - finished < 5, proc.output  # it was ~19 s
    finally:
        proc.stop()


def test_start_waits_for_master_once_and_stop_is_quiet(tmp_path: Path) -> None:
    """No node warns that the parameter server is unreachable while master starts, nor that
    master left the graph at Ctrl-C (master is stopped after the nodes)."""
    (tmp_path / "quiet.yaml").write_text(
        "nodes:\n  - module: zenros.services.master\n  - module: zenros.examples.talker\n"
        "  - module: zenros.examples.listener\n")
    proc = Proc([sys.executable, "-m", "zenros.cli", "launch", str(tmp_path / "quiet.yaml"),
                 "--data-dir", str(tmp_path / "home"), "--verbose"],
                env={"ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}",
                     "ZENROS_PREFIX": unique_prefix(), "ZENROS_HOME": str(tmp_path / "home")})
    try:
        assert proc.wait_line("waiting for master's parameter services", 20), proc.output
        assert proc.wait_line("[listener] [INFO]", 30), proc.output
        assert proc.wait_line("I heard", 20), proc.output
        proc.signal(signal.SIGINT)
        assert proc.wait(30) == 0, proc.output
        out = proc.output
        assert "WARNING" not in out, out
        talker_end = re.search(r"\[launch\] talker \(pid \d+\) (exited|was killed)", out)
        assert talker_end is not None and talker_end.start() < out.index("SIGINT to master")
    finally:
        proc.stop()


STAND_IN = """
import pathlib, sys, time
from zenros import Node, run
from zenros.errors import InvalidParameterValueError

class StandIn(Node):
    def setup(self) -> None:
        time.sleep(1.0)  # a setup that takes a while (a map to load)
        if {fail!r}:
            raise InvalidParameterValueError("parameter 'map': cannot read map YAML")
        pathlib.Path({marker!r}).touch()

run(StandIn)
"""


def _stand_in(tmp_path: Path, name: str, fail: bool) -> Path:
    marker = tmp_path / f"{name}-set-up"
    script = tmp_path / f"{name}.py"
    script.write_text(STAND_IN.format(fail=fail, marker=str(marker)))
    return script


def _launch(tmp_path: Path, text: str) -> Proc:
    (tmp_path / "l.yaml").write_text(text)
    return Proc([sys.executable, "-m", "zenros.cli", "launch", str(tmp_path / "l.yaml"),
                 "--data-dir", str(tmp_path / "home")],
                env={"ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}",
                     "ZENROS_PREFIX": unique_prefix()})


@pytest.mark.timeout(150)
def test_ready_is_printed_once_the_node_is_set_up(tmp_path: Path) -> None:
    script = _stand_in(tmp_path, "slow", fail=False)
    proc = _launch(tmp_path, f"nodes:\n  - {{cmd: [{sys.executable}, {script}], name: slow,"
                             " ros_args: true}\n")
    try:
        assert proc.wait_line("[launch] slow is ready", 60), proc.output
        assert (tmp_path / "slow-set-up").exists(), proc.output  # setup had completed
    finally:
        proc.stop(timeout=20)


@pytest.mark.timeout(150)
def test_a_node_refusing_its_configuration_is_never_ready_nor_restarted(
    tmp_path: Path,
) -> None:
    script = _stand_in(tmp_path, "bad", fail=True)
    proc = _launch(tmp_path, f"nodes:\n  - {{cmd: [{sys.executable}, {script}], name: bad,"
                             " ros_args: true, respawn: true}\n"
                             "  - {module: zenros.examples.listener}\n")
    try:
        assert proc.wait_line("[launch] bad could not start", 60), proc.output
        assert proc.wait_line("[launch] listener is ready", 60), proc.output
        time.sleep(1.5)  # past a respawn's 1 s: nothing comes back
        out = proc.output
        assert "bad is ready" not in out, out
        assert out.count("[launch] started bad") == 1, out
        assert out.count("startup failed: parameter 'map': cannot read map YAML") == 1, out
    finally:
        proc.stop(timeout=20)
