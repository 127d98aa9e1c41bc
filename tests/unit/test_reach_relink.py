"""`Reach`'s ``relink``: a goal's client waits for a server that was listed, and left with a
lost link, to be listed again; without ``relink`` (services) it gives up at once."""

from __future__ import annotations

from typing import Any

import pytest
from zenros import reach
from zenros.reach import Reach


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


@pytest.fixture
def clock(monkeypatch: pytest.MonkeyPatch) -> Clock:
    c = Clock()
    monkeypatch.setattr(reach.time, "monotonic", c)
    return c


class Listed:
    def __init__(self, *states: bool) -> None:
        self.states = list(states)

    def __call__(self) -> bool:
        return self.states.pop(0) if len(self.states) > 1 else self.states[0]


def test_without_relink_an_unlisted_server_ends_the_request_at_once(clock: Any) -> None:
    r = Reach(Listed(False), timeout=10, grace=5)
    assert r.again() is None


def test_a_server_that_left_and_comes_back_is_asked_again(clock: Any) -> None:
    listed = Listed(True, False, False, True)  # at the start, then after each unanswered query
    r = Reach(listed, timeout=60, grace=5, relink=3)
    pauses = []
    for _ in range(3):
        pause = r.again()
        assert pause is not None
        pauses.append(pause)
        clock.now += pause
    assert pauses[0] >= reach.RELINK_POLL  # waiting for the link, not hammering the network


def test_a_server_listed_again_gets_a_new_grace(clock: Any) -> None:
    r = Reach(Listed(True, False, True, True), timeout=60, grace=1, relink=3)
    clock.now += 0.9  # the first query took most of the grace
    assert r.again() is not None  # unlisted: waiting for it
    clock.now += 2.0
    assert r.again() is not None  # listed again: a fresh grace for its routes
    clock.now += 0.5
    assert r.again() is not None


def test_relink_gives_up_when_the_server_stays_away(clock: Any) -> None:
    r = Reach(Listed(True, False), timeout=60, grace=5, relink=3)
    assert r.again() is not None
    clock.now += 2.0
    assert r.again() is not None
    clock.now += 1.0
    assert r.again() is None


def test_relink_never_outlasts_the_request(clock: Any) -> None:
    r = Reach(Listed(True, False), timeout=2, grace=1, relink=3)  # explicit relink
    assert r.again() is not None
    clock.now += 1.95
    assert r.again() is None


def test_a_server_never_listed_is_not_waited_for(clock: Any) -> None:
    r = Reach(Listed(False), timeout=60, grace=5, relink=3)
    assert r.again() is None


def test_a_goal_attempt_waits_answer_wait_doubling_up_to_the_cap(clock: Any) -> None:
    r = Reach(Listed(True), timeout=60, grace=5, relink=3)
    waits = [r.attempt() for _ in range(4)]
    assert waits == [reach.ANSWER_WAIT, 2 * reach.ANSWER_WAIT, reach.MAX_ANSWER_WAIT,
                     reach.MAX_ANSWER_WAIT]
    clock.now += 59
    assert r.attempt() == pytest.approx(1.0)  # never past the request's timeout
    assert r.resend()
    clock.now += 1
    assert not r.resend()
