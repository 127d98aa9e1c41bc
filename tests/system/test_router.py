"""The router runner as a process (start, SIGINT/SIGTERM, port in use) and in a thread."""

from __future__ import annotations

import signal
import socket
import subprocess
import sys
import threading

import pytest
import zenoh
from zenros.router import build_router_config, router_reachable, serve_router
from zenros.testing import free_port
from zenros.testing import wait_until as until

pytestmark = pytest.mark.system


def wait_until(condition: threading.Event | subprocess.Popen[str] | str, timeout: float = 10.0
               ) -> None:
    """Wait for an event to be set, a process to exit, or an endpoint to accept TCP
    (`zenros.testing.wait_until`: a timeout says which)."""
    if isinstance(condition, threading.Event):
        pred, what = condition.is_set, "the event to be set"
    elif isinstance(condition, str):
        endpoint = condition
        pred, what = (lambda: router_reachable(endpoint, 0.2)), f"{endpoint} to accept TCP"
    else:
        proc = condition
        pred, what = (lambda: proc.poll() is not None), f"process {proc.pid} to exit"
    until(pred, timeout, 0.01, what=what)


def start(*args: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "zenros.router", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def stop(proc: subprocess.Popen[str]) -> None:
    if proc.poll() is None:
        proc.kill()
    proc.communicate()


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_router_process_serves_then_exits_cleanly(sig: signal.Signals) -> None:
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    proc = start("-l", endpoint)
    try:
        wait_until(endpoint)
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=10)
        assert proc.returncode == 0, err
        assert f"router listening on {endpoint}" in err
    finally:
        stop(proc)


def test_port_in_use_exits_3_with_one_line() -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        endpoint = f"tcp/127.0.0.1:{taken.getsockname()[1]}"
        proc = start("-l", endpoint)
        try:
            _, err = proc.communicate(timeout=20)
        finally:
            stop(proc)
    assert proc.returncode == 3
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"zenros router: cannot listen on {endpoint}")
    assert "Address already in use" in lines[0]


def test_serve_router_in_a_thread_with_a_stop_event() -> None:
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    ready, stop_event = threading.Event(), threading.Event()
    zids: list[str] = []

    def on_ready(session: zenoh.Session) -> None:
        zids.append(str(session.zid()))
        ready.set()

    codes: list[int] = []
    config = build_router_config([endpoint])
    thread = threading.Thread(target=lambda: codes.append(serve_router(config, on_ready,
                                                                       stop=stop_event)))
    thread.start()
    try:
        wait_until(ready)
        assert router_reachable(endpoint, 1.0)
    finally:
        stop_event.set()
        thread.join(10)
    assert codes == [0] and zids
    assert not router_reachable(endpoint, 1.0)
