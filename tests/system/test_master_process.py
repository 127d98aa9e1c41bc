"""The master as a process: no acknowledged write lost to kill -9, a restart serves the same
values, and `zenros param` drives it."""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from pathlib import Path

import pytest
from zenros.cli import param as param_cli
from zenros.context import Context
from zenros.errors import ZenrosError
from zenros.node import Node
from zenros.param_client import ParameterClient
from zenros.testing import Proc

pytestmark = pytest.mark.system


def start_master(router: str, prefix: str, home: Path) -> Proc:
    proc = Proc([sys.executable, "-m", "zenros.services.master", "-e", router, "--prefix", prefix],
                env={"ZENROS_HOME": str(home)})
    assert proc.wait_line("started", 15), proc.output
    return proc


@pytest.fixture
def ctx(observer: Context) -> Context:
    return observer


def test_kill_9_loses_no_acknowledged_write(router: str, prefix: str, tmp_path: Path,
                                            ctx: Context, procs: list[Proc]) -> None:
    procs.append(master := start_master(router, prefix, tmp_path))
    client = ParameterClient(ctx, timeout=3.0)
    assert client.wait_for_master(10)
    client.set("/robot/name", "r1")
    acked: list[int] = []
    enough = threading.Event()

    def writer() -> None:
        for i in range(100_000):
            try:
                client.set(f"/log/n{i}", {"i": i, "half": i / 2})
            except ZenrosError:
                return
            acked.append(i)
            if len(acked) >= 40:
                enough.set()

    thread = threading.Thread(target=writer, daemon=True)
    thread.start()
    assert enough.wait(30)
    master.signal(signal.SIGKILL)  # mid-stream: the writer is inside a set right now
    assert master.wait(10) == -signal.SIGKILL
    thread.join(15)
    assert not thread.is_alive()

    procs.append(start_master(router, prefix, tmp_path))
    graph = ctx.graph
    assert graph.wait_for(lambda: len(graph.servers("/master/set_param")) == 1, 10)
    assert client.get("/robot/name") == "r1"
    stored = client.get("/log")
    for i in acked:
        assert stored[f"n{i}"] == {"i": i, "half": i / 2}
    assert len(stored) in (len(acked), len(acked) + 1)  # plus, maybe, the one in flight


def test_a_second_master_on_the_same_data_dir_fails_at_startup(
    router: str, prefix: str, tmp_path: Path, procs: list[Proc]
) -> None:
    procs.append(start_master(router, prefix, tmp_path))
    second = Proc([sys.executable, "-m", "zenros.services.master", "-e", router, "--prefix",
                   prefix, "--name", "master_b"], env={"ZENROS_HOME": str(tmp_path)})
    procs.append(second)
    assert second.wait(15) == 3, second.output
    assert "in use by another process" in second.output


TWIN = """
import sys, threading
from zenros.context import Context
from zenros.log import configure_logging
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.shutdown import install_shutdown_listener

configure_logging(None)
ctx = Context(SessionOptions(connect=[sys.argv[1]]), prefix=sys.argv[2])
node = Node("twin", context=ctx)
stop = threading.Event()
install_shutdown_listener(node, stop.set)  # what the runtime does with its stop event
print("ready", flush=True)
stop.wait(30)
node.close()
ctx.close()
sys.exit(0 if stop.is_set() else 1)
"""


def test_an_older_node_process_exits_when_a_newer_one_takes_its_name(
    router: str, prefix: str, tmp_path: Path, ctx: Context, procs: list[Proc]
) -> None:
    procs.append(start_master(router, prefix, tmp_path))
    older = Proc([sys.executable, "-c", TWIN, router, prefix])
    procs.append(older)
    assert older.wait_line("ready", 15), older.output
    assert ctx.graph.wait_for_node("/twin", 10)
    newer = Node("twin", context=ctx)
    try:
        assert older.wait(15) == 0, older.output
        assert "shutting down: a newer node took the name /twin" in older.output
        assert procs[0].wait_line("duplicate node name /twin", 5), procs[0].output
        graph = ctx.graph
        assert graph.wait_for(lambda: [n.zid for n in graph.nodes() if n.name == "/twin"]
                              == [ctx.zid], 5)
    finally:
        newer.close()


def run_cli(capsys: pytest.CaptureFixture[str], router: str, prefix: str, *argv: str) -> str:
    parser = argparse.ArgumentParser(prog="zenros")
    param_cli.register(parser.add_subparsers(dest="noun", required=True))
    args = parser.parse_args(["param", *argv, "-e", router, "--prefix", prefix])
    capsys.readouterr()
    assert args.func(args) == 0
    return capsys.readouterr().out


def test_param_cli_against_a_master_process(router: str, prefix: str, tmp_path: Path,
                                            procs: list[Proc],
                                            capsys: pytest.CaptureFixture[str]) -> None:
    procs.append(start_master(router, prefix, tmp_path / "home"))

    def cli(*argv: str) -> str:
        return run_cli(capsys, router, prefix, *argv)

    cli("set", "/nav/max_speed", "0.5")
    cli("set", "/nav/limits", "{v: 1, w: [1, 2]}")
    assert cli("get", "/nav/max_speed") == "0.5\n"
    assert cli("get", "/nav/limits", "--json") == '{"v": 1, "w": [1, 2]}\n'
    assert cli("list") == "/nav/limits/v\n/nav/limits/w\n/nav/max_speed\n"
    dump = tmp_path / "nav.yaml"
    cli("dump", "/nav", "-o", str(dump))
    assert "ros__parameters" in dump.read_text()
    cli("delete", "--namespace", "/nav")
    assert cli("list") == ""
    assert "loaded 3 parameters" in cli("load", str(dump), "/copy")
    assert cli("list", "/copy") == (
        "/copy/nav/limits/v\n/copy/nav/limits/w\n/copy/nav/max_speed\n")
    assert procs[0].stop() == 0, procs[0].output  # SIGINT: a clean exit


def test_param_cli_reports_a_missing_master(router: str, prefix: str) -> None:
    parser = argparse.ArgumentParser(prog="zenros")
    param_cli.register(parser.add_subparsers(dest="noun", required=True))
    args = parser.parse_args(["param", "list", "-e", router, "--prefix", prefix,
                              "--timeout", "0.5"])
    with pytest.raises(ZenrosError, match="no master reachable"):
        args.func(args)
