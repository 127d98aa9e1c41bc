"""Node processes under `run()`: clean shutdown, startup failures, and graph departures."""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import time

import pytest
from zenros.context import Context
from zenros.testing import Proc, free_port, unique_prefix

pytestmark = pytest.mark.system


def _node(module: str, router: str, prefix: str, *extra: str) -> Proc:
    return Proc([sys.executable, "-m", module, "-e", router, "--prefix", prefix, *extra])


def test_sigint_ends_a_node_cleanly(router: str, prefix: str, observer: Context,
                                    procs: list[Proc]) -> None:
    p = _node("zenros.examples.talker", router, prefix)
    procs.append(p)
    assert observer.graph.wait_for_node("/talker", 10), p.output
    p.signal(signal.SIGINT)
    assert p.wait(10) == 0, p.output
    assert "shutting down" in p.output
    g = observer.graph
    assert g.wait_for(lambda: "/talker" not in g.node_names(), 5)


def test_sigterm_ends_a_node_cleanly(router: str, prefix: str, observer: Context,
                                     procs: list[Proc]) -> None:
    p = _node("zenros.examples.listener", router, prefix)
    procs.append(p)
    assert observer.graph.wait_for_node("/listener", 10), p.output
    p.signal(signal.SIGTERM)
    assert p.wait(10) == 0, p.output


@pytest.mark.parametrize(("signum", "within"), [(signal.SIGKILL, 2.0), (signal.SIGSTOP, 3.0)])
def test_killed_node_leaves_the_graph_within_2s_and_a_frozen_one_within_3s(
    router: str, prefix: str, observer: Context, procs: list[Proc], signum: int, within: float
) -> None:
    # killed: its TCP links close at once; frozen: its 2.5 s lease runs out (docs/wire.md)
    p = _node("zenros.examples.talker", router, prefix, "--name", "victim")
    procs.append(p)
    g = observer.graph
    assert g.wait_for(lambda: "/victim" in g.node_names() and "/chatter" in g.topics(), 10)
    start = time.monotonic()
    p.signal(signum)
    try:
        assert g.wait_for(lambda: "/victim" not in g.node_names()
                          and "/chatter" not in g.topics(), within)
        assert time.monotonic() - start < within
    finally:
        if signum == signal.SIGSTOP:
            p.signal(signal.SIGCONT)


@pytest.mark.parametrize(
    "args, needle",
    [
        (["-m", "client", "-e", "tcp/127.0.0.1:{port}"], "cannot open Zenoh session"),
        (["--name", "1bad"], "invalid node name"),
        (["-p", "rate:=fast"], "parameter 'rate' is float"),
        (["-r", "nonsense"], "invalid remapping"),
        (["--params-file", "/nonexistent/params.yaml"], "cannot read params file"),
    ],
)
def test_startup_failure_exits_3_with_one_line(args: list[str], needle: str) -> None:
    port = free_port()
    argv = [a.format(port=port) for a in args]
    if "-e" not in argv:
        argv += ["-e", f"tcp/127.0.0.1:{port}", "--cfg", "connect/exit_on_failure:false"]
    p = Proc([sys.executable, "-m", "zenros.examples.talker", "--prefix", unique_prefix(), *argv])
    try:
        assert p.wait(20) == 3, p.output
    finally:
        p.stop()
    # One line says why (a warning that master is unreachable may come before it).
    failures = [ln for ln in p.lines if "startup failed" in ln or "Traceback" in ln]
    assert len(failures) == 1 and needle in failures[0], p.output
    assert p.lines[-1] == failures[0]


def test_usage_error_exits_2() -> None:
    p = Proc([sys.executable, "-m", "zenros.examples.talker", "--no-such-flag"])
    try:
        assert p.wait(20) == 2
    finally:
        p.stop()


def test_node_process_serves_across_processes(router: str, prefix: str, observer: Context,
                                              procs: list[Proc]) -> None:
    from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsRequest
    from zenros.rpc import Client

    procs.append(_node("zenros.examples.add_two_ints_server", router, prefix))
    client = Client(observer, AddTwoInts, "/add_two_ints")
    assert client.wait_for_service(10)
    assert client.call(AddTwoIntsRequest(a=20, b=22)).sum == 42


FAILING_NODE = """
from zenros import ConfigError, Node, run
from zenros.msgs.std_msgs import String

class Failing(Node):
    def setup(self):
        self.create_publisher(String, "out")
        if self.declare_parameter("fail", "bug") == "bug":
            len(3)                       # a TypeError: a bug, not the configuration
        raise ConfigError("parameter 'fail': the configuration is refused")

run(Failing)
"""


@pytest.mark.parametrize(
    "fail, code, needle",
    [("bug", 1, "TypeError: object of type 'int' has no len()"),
     ("config", 3, "startup failed: parameter 'fail': the configuration is refused")],
)
def test_a_bug_in_setup_exits_1_and_a_refused_configuration_3(
    router: str, prefix: str, fail: str, code: int, needle: str
) -> None:
    """Exit code 3 stops a launch ("running it again cannot help"), so only a `ConfigError`
    (and the session, names and parameter values) maps to it; a TypeError raised by a bug in
    ``setup()`` exits 1, with its traceback, and gets the supervisor's crash handling."""
    p = Proc([sys.executable, "-c", FAILING_NODE, "-e", router, "--prefix", prefix,
              "-p", f"fail:={fail}"])
    try:
        assert p.wait(60) == code, p.output
    finally:
        p.stop()
    assert needle in p.output
    assert ("Traceback" in p.output) == (code == 1), p.output


STUCK_NODE = """
import threading
from zenros import Node, run

class Stuck(Node):
    def close(self):
        threading.Event().wait()   # a shutdown that never finishes

run(Stuck)
"""


def test_second_signal_forces_exit(router: str, prefix: str, observer: Context) -> None:
    p = Proc([sys.executable, "-c", STUCK_NODE, "-e", router, "--prefix", prefix])
    try:
        assert observer.graph.wait_for_node("/stuck", 10), p.output
        p.signal(signal.SIGINT)
        assert p.wait_line("shutting down", 10), p.output
        p.signal(signal.SIGINT)
        assert p.wait(10) == 130, p.output
        assert "forced exit" in p.output
    finally:
        p.stop()


def _tgkill(pid: int, tid: int, sig: int) -> None:
    """Send ``sig`` to one thread (``tid``) of process ``pid``."""
    libc = ctypes.CDLL(None, use_errno=True)
    if not hasattr(libc, "tgkill"):
        pytest.skip("this libc has no tgkill (glibc 2.30+)")
    if libc.tgkill(pid, tid, sig) != 0:
        raise OSError(ctypes.get_errno(), f"tgkill({pid}, {tid})")


def test_second_signal_forces_exit_when_another_thread_takes_it(
        router: str, prefix: str, observer: Context) -> None:
    """The kernel hands a process's signal to any of its threads, Zenoh's too; then only the
    main thread's flag is set, and its handler runs when it wakes. A close that never ends
    must not hold the main thread (it failed so in a full suite run, 2026-12-05)."""
    p = Proc([sys.executable, "-c", STUCK_NODE, "-e", router, "--prefix", prefix])
    try:
        assert observer.graph.wait_for_node("/stuck", 10), p.output
        p.signal(signal.SIGINT)
        assert p.wait_line("shutting down", 10), p.output
        pid = p.popen.pid
        others = [int(t) for t in os.listdir(f"/proc/{pid}/task") if int(t) != pid]
        assert others, "the node runs Zenoh's threads beside its main one"
        _tgkill(pid, others[-1], signal.SIGINT)
        assert p.wait(10) == 130, p.output
        assert "forced exit" in p.output
    finally:
        p.stop()
