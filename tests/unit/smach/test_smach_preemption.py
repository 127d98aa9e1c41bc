"""Preemption across containers, and running a machine in the background."""

from __future__ import annotations

import asyncio
import threading
from typing import cast

import pytest
from zenros.errors import InvalidUserCodeError, ZenrosTimeout
from zenros.smach import CBState, Concurrence, State, StateMachine, UserDataAccess
from zenros.smach.doubles import FixedOutcome, RaiseState, SucceedState, WaitForPreempt


class Polite(State):
    """Checks the flag once and reports what it saw (never blocks)."""

    def __init__(self) -> None:
        super().__init__(["succeeded", "preempted"])
        self.saw_preempt = False

    def execute(self, userdata: UserDataAccess) -> str:
        if self.preempt_requested():
            self.saw_preempt = True
            self.service_preempt()
            return "preempted"
        return "succeeded"


def test_preempt_reaches_the_running_state_and_ends_the_machine() -> None:
    sm = StateMachine(outcomes=["succeeded", "preempted"])
    waiter = WaitForPreempt(outcomes=["succeeded"])
    after = SucceedState()
    sm.add("WAIT", waiter, transitions={"succeeded": "AFTER"})
    sm.add("AFTER", after)
    run = sm.execute_in_thread()
    assert waiter.entered.wait(5)
    run.request_preempt()
    assert run.result(5) == "preempted"
    assert after.executions == 0
    assert not sm.preempt_requested() and not waiter.preempt_requested()


def test_preempt_propagates_through_nested_containers() -> None:
    inner = StateMachine(outcomes=["succeeded", "preempted"])
    waiter = WaitForPreempt(outcomes=["succeeded"])
    inner.add("WAIT", waiter)
    outer = StateMachine(outcomes=["succeeded", "preempted"])
    outer.add("INNER", inner)
    run = outer.execute_in_thread()
    assert waiter.entered.wait(5)
    assert outer.get_status().active_paths == ["/INNER/WAIT"]
    run.request_preempt()
    assert run.result(5) == "preempted"
    assert not any(s.preempt_requested() for s in (outer, inner, waiter))


def test_preempt_of_a_concurrence_inside_a_machine() -> None:
    cc = Concurrence(outcomes=["done", "preempted"], default_outcome="done")
    a, b = WaitForPreempt(), WaitForPreempt()
    cc.add("A", a)
    cc.add("B", b)
    sm = StateMachine(outcomes=["done", "preempted"])
    sm.add("BOTH", cc)
    run = sm.execute_in_thread()
    assert a.entered.wait(5) and b.entered.wait(5)
    assert sorted(sm.get_status().active_paths) == ["/BOTH/A", "/BOTH/B"]
    run.request_preempt()
    assert run.result(5) == "preempted"


def test_a_serviced_preempt_is_spent_so_a_cleanup_state_runs_normally() -> None:
    sm = StateMachine(outcomes=["cleaned"])
    waiter = WaitForPreempt()
    cleanup = Polite()
    sm.add("WAIT", waiter, transitions={"preempted": "CLEANUP"})
    sm.add("CLEANUP", cleanup, transitions={"succeeded": "cleaned", "preempted": "cleaned"})
    run = sm.execute_in_thread()
    assert waiter.entered.wait(5)
    run.request_preempt()
    assert run.result(5) == "cleaned"
    assert cleanup.saw_preempt is False


def test_an_ignored_preempt_moves_on_to_the_next_state() -> None:
    sm = StateMachine(outcomes=["succeeded", "preempted"])
    stubborn = WaitForPreempt(outcomes=["succeeded"], services=False)
    polite = Polite()
    sm.add("STUBBORN", stubborn, transitions={"preempted": "POLITE"})
    sm.add("POLITE", polite)
    run = sm.execute_in_thread()
    assert stubborn.entered.wait(5)
    run.request_preempt()
    assert run.result(5) == "preempted"
    assert polite.saw_preempt
    assert not stubborn.preempt_requested()  # recalled when the request moved on


def test_a_preempt_before_execute_is_seen_by_the_first_state() -> None:
    sm = StateMachine(outcomes=["succeeded", "preempted"])
    polite = Polite()
    sm.add("POLITE", polite)
    sm.request_preempt()
    assert sm.execute() == "preempted"
    assert polite.saw_preempt


def test_an_unserviced_request_expires_with_the_root_run() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    sm.add("A", SucceedState())
    sm.request_preempt()
    assert sm.execute() == "succeeded"  # nobody looked at the flag
    assert not sm.preempt_requested()
    assert not sm["A"].preempt_requested()


def test_unserviced_inner_preempt_stays_up_for_the_parent() -> None:
    inner = StateMachine(outcomes=["succeeded", "preempted"])
    inner.add("STUBBORN", WaitForPreempt(outcomes=["succeeded"], services=False))
    outer = StateMachine(outcomes=["succeeded", "preempted"])
    polite = Polite()
    outer.add("INNER", inner, transitions={"preempted": "POLITE"})
    outer.add("POLITE", polite)
    run = outer.execute_in_thread()
    assert cast(WaitForPreempt, inner["STUBBORN"]).entered.wait(5)
    run.request_preempt()
    assert run.result(5) == "preempted"
    assert polite.saw_preempt


def test_execution_result_timeout_and_repr() -> None:
    sm = StateMachine(outcomes=["preempted"])
    waiter = WaitForPreempt()
    sm.add("WAIT", waiter)
    run = sm.execute_in_thread()
    assert waiter.entered.wait(5)
    assert "running" in repr(run)
    with pytest.raises(ZenrosTimeout, match=r"did not finish within 0 s; active: \['WAIT'\]"):
        run.result(timeout=0)
    done = threading.Event()
    run.add_done_callback(lambda r: done.set())
    run.request_preempt()
    assert done.wait(5) and run.done() and run.join(5)
    assert "done" in repr(run)


def test_execution_carries_the_exception() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    sm.add("BOOM", RaiseState(RuntimeError("no")))
    run = sm.execute_in_thread()
    with pytest.raises(InvalidUserCodeError, match="raised RuntimeError: no"):
        run.result(5)
    assert not sm.is_running


def test_execute_in_thread_checks_wiring_in_the_caller() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    sm.add("A", FixedOutcome("x"))
    with pytest.raises(ValueError, match="A.x"):
        sm.execute_in_thread()
    assert not sm.is_running


async def test_an_execution_can_be_awaited() -> None:
    sm = StateMachine(outcomes=["preempted"])
    waiter = WaitForPreempt()
    sm.add("WAIT", waiter)
    run = sm.execute_in_thread()
    assert await asyncio.to_thread(waiter.entered.wait, 5)
    run.request_preempt()
    assert await asyncio.wait_for(run, 5) == "preempted"


def test_cooperative_states_poll_the_flag() -> None:
    ticks = threading.Semaphore(0)

    def worker(ud: UserDataAccess) -> str:
        state = sm["WORK"]
        while not state.preempt_requested():
            ticks.release()
            state.wait_for_preempt(0.01)
        state.service_preempt()
        return "preempted"

    sm = StateMachine(outcomes=["succeeded", "preempted"])
    sm.add("WORK", CBState(worker, outcomes=["succeeded", "preempted"]))
    run = sm.execute_in_thread()
    assert ticks.acquire(timeout=5)
    run.request_preempt()
    assert run.result(5) == "preempted"
