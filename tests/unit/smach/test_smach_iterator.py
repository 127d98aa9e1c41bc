"""Iterator: one contained state per item, loop and break outcomes, exhaustion, preemption."""

from __future__ import annotations

from collections.abc import Iterator as PyIterator
from typing import Any, cast

import pytest
from zenros.errors import InvalidStateError, InvalidTransitionError, InvalidUserCodeError
from zenros.smach import CBState, Iterator, StateMachine, UserDataAccess
from zenros.smach.doubles import SucceedState, WaitForPreempt


def visit(log: list[object], stop_at: object = None) -> CBState:
    def cb(ud: UserDataAccess) -> str:
        log.append(ud.item)
        return "found" if ud.item == stop_at else "next"

    return CBState(cb, outcomes=["next", "found", "aborted"], input_keys=["item"])


def test_visits_every_item_then_exhausts() -> None:
    log: list[object] = []
    it = Iterator(outcomes=["found", "aborted"], it=[1, 2, 3], it_label="item")
    it.set_contained_state("VISIT", visit(log), loop_outcomes=["next"])
    assert "exhausted" in it.outcomes
    assert it.execute() == "exhausted"
    assert log == [1, 2, 3]


def test_break_outcome_ends_early() -> None:
    log: list[object] = []
    it = Iterator(outcomes=["found", "aborted"], it=[1, 2, 3], it_label="item")
    it.set_contained_state("VISIT", visit(log, stop_at=2), loop_outcomes=["next"])
    assert it.execute() == "found"
    assert log == [1, 2]


def test_final_outcome_map_renames_break_outcomes() -> None:
    it = Iterator(outcomes=["hit", "aborted"], it=[1, 2], it_label="item", exhausted_outcome="miss")
    it.set_contained_state("VISIT", visit([], stop_at=1), break_outcomes=["found", "aborted"],
                           final_outcome_map={"found": "hit"})
    assert it.execute() == "hit"
    assert it.outcomes == ("hit", "aborted", "miss")


def test_break_outcomes_make_the_rest_loop() -> None:
    log: list[object] = []
    it = Iterator(outcomes=["found", "aborted"], it=range(5), it_label="item")
    it.set_contained_state("VISIT", visit(log, stop_at=3), break_outcomes=["found", "aborted"])
    assert it.execute() == "found"
    assert log == [0, 1, 2, 3]


def test_a_function_gives_fresh_items_every_run() -> None:
    log: list[object] = []

    def items() -> PyIterator[int]:
        yield from (1, 2)

    it = Iterator(outcomes=["found", "aborted"], it=items, it_label="item")
    it.set_contained_state("VISIT", visit(log), loop_outcomes=["next"])
    assert it.execute() == "exhausted"
    assert it.execute() == "exhausted"
    assert log == [1, 2, 1, 2]


def test_remapping_the_item_key() -> None:
    seen: list[object] = []
    it = Iterator(outcomes=["done"], it=["a", "b"], exhausted_outcome="done")

    def cb(ud: UserDataAccess) -> str:
        seen.append(ud.target)
        return "succeeded"

    it.set_contained_state("GO", CBState(cb, outcomes=["succeeded"], input_keys=["target"]),
                           loop_outcomes=["succeeded"], remapping={"target": "it_data"})
    assert it.execute() == "done"
    assert seen == ["a", "b"]


def test_accumulates_into_output_keys_inside_a_machine() -> None:
    def add(ud: UserDataAccess) -> str:
        ud.total = ud.total + ud.it_data
        return "succeeded"

    it = Iterator(outcomes=["done"], it=[1, 2, 3], exhausted_outcome="done",
                  input_keys=["total"], output_keys=["total"])
    it.set_contained_state("ADD", CBState(add, outcomes=["succeeded"], io_keys=["total", "it_data"]
                                          ), loop_outcomes=["succeeded"])
    sm = StateMachine(outcomes=["done"])
    sm.userdata.total = 10
    sm.add("SUM", it)
    assert sm.execute() == "done"
    assert sm.userdata.total == 16


def test_empty_items_exhaust_at_once() -> None:
    state = SucceedState()
    it = Iterator(outcomes=["x"], it=[])
    it.set_contained_state("S", state, loop_outcomes=["succeeded"])
    assert it.execute() == "exhausted"
    assert state.executions == 0


def test_errors_from_the_items_are_wrapped() -> None:
    def broken() -> PyIterator[int]:
        yield 1
        raise OSError("disk")

    it = Iterator(outcomes=["x"], it=broken)
    it.set_contained_state("S", SucceedState(), loop_outcomes=["succeeded"])
    with pytest.raises(InvalidUserCodeError, match="the items of / raised OSError: disk"):
        it.execute()
    it2 = Iterator(outcomes=["x"], it=cast(Any, lambda: 5))
    it2.set_contained_state("S", SucceedState(), loop_outcomes=["succeeded"])
    with pytest.raises(InvalidUserCodeError, match="could not be iterated: TypeError"):
        it2.execute()


def test_preempt_stops_between_items_with_preempted() -> None:
    waiter = WaitForPreempt(outcomes=["succeeded"])
    it = Iterator(outcomes=["preempted"], it=range(100))
    it.set_contained_state("WAIT", waiter, loop_outcomes=["succeeded", "preempted"])
    run = it.execute_in_thread()
    assert waiter.entered.wait(5)
    assert it.get_active_states() == ["WAIT"]
    assert it.get_status().info["index"] == 0
    run.request_preempt()
    assert run.result(5) == "preempted"
    assert waiter.executions == 1
    assert not it.preempt_requested() and not waiter.preempt_requested()


def test_preempt_without_preempted_outcome_is_passed_to_the_next_item() -> None:
    waiter = WaitForPreempt(outcomes=["succeeded"], services=False)
    it = Iterator(outcomes=["stopped"], it=range(3))
    it.set_contained_state("WAIT", waiter, loop_outcomes=["succeeded", "preempted"])
    run = it.execute_in_thread()
    assert waiter.entered.wait(5)
    run.request_preempt()
    # the state ignores (does not service) the preempt, so each next item sees it too
    assert run.result(5) == "exhausted"
    assert waiter.executions == 3


def test_break_on_preempted_maps_like_any_break_outcome() -> None:
    waiter = WaitForPreempt(outcomes=["succeeded"])
    it = Iterator(outcomes=["cancelled"], it=range(3))
    it.set_contained_state("WAIT", waiter, break_outcomes=["preempted"],
                           final_outcome_map={"preempted": "cancelled"})
    run = it.execute_in_thread()
    assert waiter.entered.wait(5)
    run.request_preempt()
    assert run.result(5) == "cancelled"


def test_contained_state_configuration_errors() -> None:
    it = Iterator(outcomes=["done"], it=[1])
    with pytest.raises(InvalidTransitionError, match="has no outcomes nxt; its outcomes: found,"
                       " next"):
        it.set_contained_state("S", CBState(lambda ud: "next", outcomes=["next", "found"]),
                               loop_outcomes=["nxt"])
    with pytest.raises(InvalidStateError, match="loop_outcomes or break_outcomes"):
        it.set_contained_state("S", SucceedState())
    with pytest.raises(InvalidStateError, match="must split its outcomes"):
        it.set_contained_state("S", SucceedState(outcomes=["aborted"]),
                               loop_outcomes=["succeeded"], break_outcomes=["succeeded"])
    with pytest.raises(InvalidTransitionError, match="maps to nowhere, which are not container"
                       " outcomes"):
        it.set_contained_state("S", SucceedState(), break_outcomes=["succeeded"],
                               final_outcome_map={"succeeded": "nowhere"})
    it.set_contained_state("S", SucceedState(), loop_outcomes=["succeeded"])
    with pytest.raises(InvalidStateError, match="already iterates S; an Iterator holds one state"):
        it.set_contained_state("T", SucceedState(), loop_outcomes=["succeeded"])


def test_unmapped_break_outcome_is_a_wiring_error() -> None:
    it = Iterator(outcomes=["done"], it=[1])
    it.set_contained_state("S", SucceedState(outcomes=["aborted"]), loop_outcomes=["succeeded"])
    with pytest.raises(InvalidTransitionError, match="break outcome S.aborted of / is not a"
                       " container outcome; map it in final_outcome_map to one of done, exhausted"):
        it.execute()


def test_item_key_counts_as_provided_and_other_keys_do_not() -> None:
    it = Iterator(outcomes=["done"], it=[1], it_label="wp")
    it.set_contained_state("S", CBState(lambda ud: "ok", outcomes=["ok"], input_keys=["wp", "speed"]),
                           loop_outcomes=["ok"])
    with pytest.raises(InvalidStateError, match="reads key 'speed'.*available keys: wp"):
        it.check()


def test_constructor_checks() -> None:
    with pytest.raises(InvalidStateError, match="needs an iterable or a function"):
        Iterator(outcomes=["x"], it=cast(Any, 5))
    with pytest.raises(InvalidStateError, match="it_label must be a userdata key name"):
        Iterator(outcomes=["x"], it=[], it_label="")


def test_initial_state_and_structure() -> None:
    it = Iterator(outcomes=["found"], it=[1], it_label="item")
    it.set_contained_state("VISIT", visit([]), loop_outcomes=["next"],
                           final_outcome_map={"aborted": "found"})
    it.set_initial_state(["VISIT"], {"x": 1})
    with pytest.raises(InvalidStateError, match="its only state is VISIT"):
        it.set_initial_state(["OTHER"])
    s = it.get_structure()
    assert [(t.source, t.outcome, t.target, t.implicit) for t in s.transitions] == [
        ("VISIT", "next", "VISIT", False),
        ("VISIT", "found", "found", True),
        ("VISIT", "aborted", "found", False),
    ]
    assert s.info["it_label"] == "item" and s.info["break_outcomes"] == ["found", "aborted"]
