"""StatusPublisher: an idle server reports a change within STATUS_DELAY; a busy one publishes
at most one array per STATUS_INTERVAL (each array costs every client of the action)."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from zenros.action.status import STATUS_DELAY, STATUS_INTERVAL, StatusPublisher
from zenros.context import Context
from zenros.testing import loopback_options


class RecordingExecutor:
    """Records what `StatusPublisher.mark` schedules instead of running it."""

    def __init__(self) -> None:
        self.loop = self
        self.waits: list[float] = []

    def call_soon(self, fn: Callable[..., Any], *args: Any) -> None:
        fn(*args)

    def call_later(self, wait: float, fn: Callable[[], None]) -> None:
        self.waits.append(wait)


@pytest.fixture
def ctx() -> Iterator[Context]:
    c = Context(loopback_options(), prefix="zt_status")
    yield c
    c.close()


def test_a_busy_server_publishes_at_most_one_array_per_interval(ctx: Context) -> None:
    ex = RecordingExecutor()
    pub = StatusPublisher(ctx.session, "zt_status/action/x/status", ex,  # type: ignore[arg-type]
                          lambda: [], threading.RLock(), interval=10.0)
    try:
        pub.mark()
        assert ex.waits == [STATUS_DELAY]  # idle: reported at once (after the short delay)
        pub.mark()
        assert len(ex.waits) == 1  # coalesced into the pending array
        pub.flush()
        pub.mark()  # right after an array: wait out the interval
        assert 9.0 < ex.waits[1] <= 10.0
    finally:
        pub.close()


def test_the_default_interval_is_short() -> None:
    assert STATUS_DELAY <= STATUS_INTERVAL <= 0.005  # intermediate states stay observable
