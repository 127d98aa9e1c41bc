"""The shipped test doubles behave as documented."""

from __future__ import annotations

import threading

import pytest
from zenros.errors import InvalidStateError
from zenros.smach import UserData
from zenros.smach.doubles import (
    FailState,
    FixedOutcome,
    OutcomeQueue,
    RaiseState,
    SucceedState,
    WaitForPreempt,
)


def test_fixed_outcomes() -> None:
    ud = UserData()
    assert SucceedState().execute(ud) == "succeeded"
    assert FailState(outcomes=["succeeded"]).outcomes == ("succeeded", "aborted")
    f = FixedOutcome("x", outcomes=["y"])
    assert f.execute(ud) == "x" and f.execute(ud) == "x" and f.executions == 2
    assert f.outcomes == ("y", "x")


def test_outcome_queue_then_eventually_or_cycle() -> None:
    ud = UserData()
    q = OutcomeQueue(["a", "b"], eventually="c")
    assert [q.execute(ud) for _ in range(4)] == ["a", "b", "c", "c"]
    assert set(q.outcomes) == {"a", "b", "c"}
    cyc = OutcomeQueue(["a", "b"])
    assert [cyc.execute(ud) for _ in range(5)] == ["a", "b", "a", "b", "a"]
    with pytest.raises(InvalidStateError, match="at least one outcome"):
        OutcomeQueue([])


def test_raise_state() -> None:
    with pytest.raises(KeyError):
        RaiseState(KeyError("k")).execute(UserData())


def test_wait_for_preempt_release_and_preempt() -> None:
    w = WaitForPreempt(outcomes=["succeeded"])
    w.release("succeeded")  # released before running: returns at once
    assert w.execute(UserData()) == "succeeded" and w.entered.is_set()
    result: list[str] = []
    t = threading.Thread(target=lambda: result.append(w.execute(UserData())))
    w.entered.clear()
    t.start()
    assert w.entered.wait(5)
    w.request_preempt()
    t.join(5)
    assert result == ["preempted"] and not w.preempt_requested()
    with pytest.raises(InvalidStateError, match="cannot release .* with 'nope'"):
        w.release("nope")


def test_wait_for_preempt_may_ignore_the_request() -> None:
    w = WaitForPreempt(services=False)
    w.request_preempt()
    assert w.execute(UserData()) == "preempted"
    assert w.preempt_requested()
