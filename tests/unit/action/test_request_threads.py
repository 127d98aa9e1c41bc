"""`RequestThreads` (leader/followers, handed over late) against a stand-in channel."""

from __future__ import annotations

import logging
import queue
import threading
from typing import Any

import pytest
import zenoh
from zenros.action.leaders import RequestThreads
from zenros.testing import wait_for

_CLOSED = object()


class Channel:
    """A Zenoh FIFO handler stand-in: ``recv`` blocks, and raises ZError once closed."""

    def __init__(self) -> None:
        self._q: queue.Queue[Any] = queue.Queue()

    def put(self, item: Any) -> None:
        self._q.put(item)

    def close(self) -> None:
        self._q.put(_CLOSED)

    def recv(self) -> Any:
        item = self._q.get()
        if item is _CLOSED:
            self._q.put(_CLOSED)
            raise zenoh.ZError("channel is empty and closed")
        return item


class Rig:
    """Requests are ``(name, job)``: each is recorded with its thread; a job is an Event the
    goal waits on (None: no goal)."""

    def __init__(self, delay: float = 0.05, idle_timeout: float = 30.0) -> None:
        self.channel = Channel()
        self.handled: list[tuple[str, str]] = []
        self.ran: list[tuple[str, str]] = []
        self.overdue: list[str] = []
        self.failures: list[BaseException] = []
        self.threads = RequestThreads(
            "test", self.channel, self._handle, self._run, self.overdue.append,
            self.failures.append, logging.getLogger("test"), delay=delay,
            idle_timeout=idle_timeout)
        self.gates: dict[str, threading.Event] = {}

    def _handle(self, request: tuple[str, bool]) -> str | None:
        name, is_goal = request
        self.handled.append((name, threading.current_thread().name))
        if not is_goal:
            return None
        self.gates.setdefault(name, threading.Event())
        return name

    def _run(self, name: str) -> None:
        self.ran.append((name, threading.current_thread().name))
        assert self.gates[name].wait(10)

    def goal(self, name: str, *, release: bool = False) -> None:
        self.gates.setdefault(name, threading.Event())
        if release:
            self.gates[name].set()
        self.channel.put((name, True))

    def request(self, name: str) -> None:
        self.channel.put((name, False))

    def close(self) -> None:
        for g in self.gates.values():
            g.set()
        self.channel.close()
        self.threads.join(5)


@pytest.fixture
def rig() -> Any:
    made: list[Rig] = []

    def make(**kw: Any) -> Rig:
        r = Rig(**kw)
        r.threads.start()
        made.append(r)
        return r

    yield make
    for r in made:
        r.close()


def _alive(prefix: str = "test-") -> list[str]:
    return sorted(t.name for t in threading.enumerate() if t.name.startswith(prefix))


def test_a_short_goal_runs_on_the_thread_that_took_it_and_it_keeps_leading(rig: Any) -> None:
    r = rig(delay=5.0)
    for i in range(5):
        r.goal(f"g{i}", release=True)
        r.request(f"r{i}")
    assert wait_for(lambda: len(r.handled) == 10, 10)
    names = {t for _, t in r.handled} | {t for _, t in r.ran}
    assert names == {"test-1"}  # one thread did everything, in order
    assert [n for n, _ in r.handled] == [x for i in range(5) for x in (f"g{i}", f"r{i}")]
    assert r.overdue == []


def test_a_long_goal_is_detached_and_requests_go_on(rig: Any) -> None:
    r = rig(delay=0.05)
    r.goal("long")
    assert wait_for(lambda: r.overdue == ["long"], 10)  # once, after the delay
    r.request("cancel")  # served by another thread while the goal still runs
    assert wait_for(lambda: [n for n, _ in r.handled] == ["long", "cancel"], 10)
    (_, runner), = r.ran
    assert r.handled[1][1] != runner
    r.gates["long"].set()
    r.goal("next", release=True)  # the detached thread rejoins as a follower
    assert wait_for(lambda: len(r.ran) == 2, 10)
    assert r.overdue == ["long"]


def test_closing_the_channel_ends_every_thread(rig: Any) -> None:
    r = rig(delay=0.02)
    for i in range(3):
        r.goal(f"g{i}")  # three detached goals: four request threads
    assert wait_for(lambda: len(r.overdue) == 3, 10)
    assert len(_alive()) >= 4
    r.close()
    assert wait_for(lambda: _alive() == [], 10)
    assert r.failures == []


def test_idle_request_threads_end_but_one(rig: Any) -> None:
    r = rig(delay=0.02, idle_timeout=0.2)
    for i in range(3):
        r.goal(f"g{i}")
    assert wait_for(lambda: len(r.overdue) == 3, 10)
    for g in r.gates.values():
        g.set()
    assert wait_for(lambda: len([n for n in _alive() if not n.endswith("-watch")]) == 1, 10)
    r.goal("again", release=True)  # the one left still serves
    assert wait_for(lambda: len(r.ran) == 4, 10)


def test_a_failure_is_reported_and_ends_the_threads() -> None:
    """What escapes handling (the server lets only a failed session through) goes to
    ``on_failure``, and the request threads end."""
    r = Rig()
    boom = RuntimeError("session failed")

    def handle(request: Any) -> None:
        raise boom

    r.threads._handle = handle
    r.threads.start()
    try:
        r.request("x")
        assert wait_for(lambda: r.failures == [boom], 10)
        assert wait_for(lambda: _alive() == [], 10)
    finally:
        r.close()
