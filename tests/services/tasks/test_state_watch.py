"""`StateWatch`: the newest state stamped after a time, None once cancelled, `Silent` after
its silence."""

from __future__ import annotations

import threading

import pytest
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import PtzState
from zenros.services.tasks.state_watch import Silent, StateWatch


def state(sec: int) -> PtzState:
    return PtzState(header=Header(stamp=Time(sec=sec)))


def test_the_next_state_after_a_stamp() -> None:
    watch: StateWatch[PtzState] = StateWatch(silence=10.0)
    watch(state(1))
    later = threading.Timer(0.05, watch, (state(2),))
    later.start()
    got = watch.next_after(Time(sec=1), lambda: False)  # state 1 is not after 1: waits for 2
    later.join()
    assert got is not None and got.header.stamp == Time(sec=2)
    assert watch.next_after(Time(sec=0), lambda: False) is got  # the newest, at once


def test_cancel_and_silence() -> None:
    watch: StateWatch[PtzState] = StateWatch(silence=0.1)
    assert watch.next_after(Time(), lambda: True) is None
    with pytest.raises(Silent):
        watch.next_after(Time(), lambda: False)
