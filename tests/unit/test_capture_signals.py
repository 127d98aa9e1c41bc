"""`capture_signals`: a SIGINT that lands while the main thread holds the stop event's lock
(inside ``Event.wait``) still stops it; the second signal forces the exit."""

from __future__ import annotations

import signal
import sys
import threading

import pytest
from zenros.runtime import capture_signals
from zenros.testing import Proc

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
    proc = Proc([sys.executable, "-c", _CHILD])
    try:
        assert proc.wait_line("ready", 20), proc.output
        proc.signal(signal.SIGINT)
        assert proc.wait(20) == 130, proc.output
    finally:
        proc.stop()
    assert "stopping" in proc.output
    assert "forced exit; the threads were at:" in proc.output
