"""ConditionState: predicate polling with injected waiting, so nothing sleeps."""

from __future__ import annotations

import threading
from typing import Any, cast

import pytest
from zenros.errors import InvalidStateError, InvalidUserCodeError
from zenros.smach import ConditionState, StateMachine, UserData, UserDataAccess


class Script:
    """Answers a predicate from a list and records the waits asked for."""

    def __init__(self, answers: list[bool]) -> None:
        self.answers = answers
        self.waits: list[float] = []

    def cond(self, ud: UserDataAccess) -> bool:
        return self.answers.pop(0)

    def wait(self, seconds: float) -> None:
        self.waits.append(seconds)


def test_true_once_by_default() -> None:
    s = Script([True])
    assert ConditionState(s.cond, wait=s.wait).execute(UserData()) == "true"
    assert s.waits == []


def test_false_at_the_first_failure() -> None:
    s = Script([True, False])
    state = ConditionState(s.cond, max_checks=3, poll_interval=0.2, wait=s.wait)
    assert state.execute(UserData()) == "false"
    assert s.waits == [0.2] and state.checks == 1


def test_true_after_max_checks_in_a_row() -> None:
    s = Script([True, True, True])
    state = ConditionState(s.cond, max_checks=3, poll_interval=0.5, wait=s.wait)
    assert state.execute(UserData()) == "true"
    assert s.waits == [0.5, 0.5] and state.checks == 3


def test_timeout_gives_false() -> None:
    clock = iter([0.0, 0.0, 0.4, 1.1])
    s = Script([True] * 10)
    state = ConditionState(s.cond, max_checks=-1, timeout=1.0, wait=s.wait,
                           now=lambda: next(clock))
    assert state.execute(UserData()) == "false"
    assert state.checks == 2


def test_preempt_between_checks() -> None:
    answers = [True] * 5
    state: ConditionState

    def wait(seconds: float) -> None:
        if len(answers) == 3:
            state.request_preempt()

    state = ConditionState(lambda ud: answers.pop(), max_checks=-1, wait=wait)
    assert state.execute(UserData()) == "preempted"
    assert not state.preempt_requested()


def test_the_condition_is_checked_once_even_when_preempted_before() -> None:
    s = Script([False])
    state = ConditionState(s.cond, max_checks=-1, wait=s.wait)
    state.request_preempt()
    assert state.execute(UserData()) == "false"
    s2 = Script([True])
    state2 = ConditionState(s2.cond, max_checks=-1, wait=s2.wait)
    state2.request_preempt()
    assert state2.execute(UserData()) == "preempted" and state2.checks == 1


def test_default_wait_returns_at_once_on_preempt() -> None:
    """The default wait is on the preempt flag, so an hour-long interval does not delay it."""
    checked = threading.Event()

    def cond(ud: UserDataAccess) -> bool:
        checked.set()
        return True

    state = ConditionState(cond, max_checks=-1, poll_interval=3600)
    result: list[str] = []
    worker = threading.Thread(target=lambda: result.append(state.execute(UserData())))
    worker.start()
    assert checked.wait(5)
    state.request_preempt()
    worker.join(5)
    assert result == ["preempted"]


def test_reads_declared_keys_inside_a_machine() -> None:
    sm = StateMachine(outcomes=["true", "false", "preempted"])
    sm.userdata.battery = 0.9
    sm.add("CHARGED", ConditionState(lambda ud: ud.battery > 0.8, input_keys=["battery"]))
    assert sm.execute() == "true"
    sm.userdata.battery = 0.1
    assert sm.execute() == "false"


def test_predicate_errors_are_reported_with_the_state() -> None:
    sm = StateMachine(outcomes=["true", "false", "preempted"])
    sm.add("BROKEN", ConditionState(lambda ud: 1 / 0 > 0))
    with pytest.raises(InvalidUserCodeError, match=r"/BROKEN \(ConditionState\) raised"
                       r" ZeroDivisionError"):
        sm.execute()


def test_argument_checks() -> None:
    with pytest.raises(InvalidStateError, match="max_checks must be >= 1, or -1"):
        ConditionState(lambda ud: True, max_checks=0)
    with pytest.raises(InvalidStateError, match="must be >= 0"):
        ConditionState(lambda ud: True, poll_interval=-1)
    with pytest.raises(InvalidStateError, match="cond_cb must be callable"):
        ConditionState(cast(Any, True))
