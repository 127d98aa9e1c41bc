"""`capture_signals`: a SIGINT that lands while the main thread holds the stop event's lock
(inside ``Event.wait``) still stops it; the second signal forces the exit."""

from __future__ import annotations

import signal
import subprocess
import sys
import threading

import pytest
from zenros.runtime import capture_signals

pytestmark = pytest.mark.timeout(30)


def test_sigint_while_the_main_thread_holds_the_events_lock() -> None:
    stop = threading.Event()
    with capture_signals(stop.set):
        with stop._cond:  # type: ignore[attr-defined]  # as Event.wait holds it at times
            signal.raise_signal(signal.SIGINT)  # the handler runs here, in this thread
            assert not stop.is_set()
        assert stop.wait(5)


_CHILD = """
import signal, sys, threading, time
from zenros.runtime import capture_signals
stop = threading.Event()
with capture_signals(stop.set):
    print("ready", flush=True)
    while not stop.wait(0.5):
        pass
    print("stopping", flush=True)
    signal.raise_signal(signal.SIGTERM)  # a second signal: forced exit
    time.sleep(10)
"""


def test_first_signal_stops_second_forces_exit() -> None:
    proc = subprocess.Popen([sys.executable, "-c", _CHILD], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None and proc.stdout.readline() == "ready\n"
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=20)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert out == "stopping\n" and proc.returncode == 130
    assert "forced exit; the threads were at:" in err
