"""Concurrence: children on threads, outcome map, callbacks, and preempting the others."""

from __future__ import annotations

import threading
from typing import Any, cast

import pytest
from zenros.errors import InvalidStateError, InvalidTransitionError, InvalidUserCodeError
from zenros.smach import (
    CBState,
    ChildOutcomes,
    Concurrence,
    ContainerEvent,
    StateMachine,
    UserDataAccess,
)
from zenros.smach.doubles import FailState, FixedOutcome, RaiseState, SucceedState, WaitForPreempt


def test_children_really_run_at_the_same_time() -> None:
    """Each child waits for the other to have started: only concurrency gets both through."""
    barrier = threading.Barrier(2, timeout=5)

    def meet(ud: UserDataAccess) -> str:
        barrier.wait()
        return "succeeded"

    cc = Concurrence(outcomes=["ok", "failed"], default_outcome="failed",
                     outcome_map={"ok": {"A": "succeeded", "B": "succeeded"}})
    cc.add("A", CBState(meet, outcomes=["succeeded"]))
    cc.add("B", CBState(meet, outcomes=["succeeded"]))
    assert cc.execute() == "ok"


def test_default_outcome_when_no_map_entry_holds() -> None:
    cc = Concurrence(outcomes=["ok", "failed"], default_outcome="failed",
                     outcome_map={"ok": {"A": "succeeded", "B": "succeeded"}})
    cc.add("A", SucceedState())
    cc.add("B", FailState(outcomes=["succeeded"]))
    assert cc.execute() == "failed"


def test_most_specific_map_entry_wins() -> None:
    cc = Concurrence(outcomes=["some", "all", "none"], default_outcome="none",
                     outcome_map={"some": {"A": "succeeded"},
                                  "all": {"A": "succeeded", "B": "succeeded"}})
    cc.add("A", SucceedState())
    cc.add("B", SucceedState())
    assert cc.execute() == "all"


def test_outcome_cb_comes_first_and_sees_all_outcomes() -> None:
    seen: list[ChildOutcomes] = []

    def decide(outcomes: ChildOutcomes) -> str | None:
        seen.append(outcomes)
        return "custom" if outcomes["B"] == "aborted" else None

    cc = Concurrence(outcomes=["ok", "custom", "failed"], default_outcome="failed",
                     outcome_map={"ok": {"A": "succeeded"}}, outcome_cb=decide)
    cc.add("A", SucceedState())
    cc.add("B", FailState())
    assert cc.execute() == "custom"
    assert seen == [{"A": "succeeded", "B": "aborted"}]


def test_outcome_cb_returning_none_falls_back_to_the_map() -> None:
    cc = Concurrence(outcomes=["ok", "failed"], default_outcome="failed",
                     outcome_map={"ok": {"A": "succeeded"}}, outcome_cb=lambda o: None)
    cc.add("A", SucceedState())
    assert cc.execute() == "ok"


def test_outcome_cb_must_return_an_outcome() -> None:
    cc = Concurrence(outcomes=["ok"], default_outcome="ok", outcome_cb=lambda o: "nope")
    cc.add("A", SucceedState())
    with pytest.raises(InvalidUserCodeError, match="returned 'nope', which is not an outcome;"
                       " outcomes: ok"):
        cc.execute()


def test_outcome_cb_errors_are_wrapped() -> None:
    def broken(o: ChildOutcomes) -> str:
        raise RuntimeError("bug")

    cc = Concurrence(outcomes=["ok"], default_outcome="ok", outcome_cb=broken)
    cc.add("A", SucceedState())
    with pytest.raises(InvalidUserCodeError, match="outcome_cb of / raised RuntimeError: bug"):
        cc.execute()


def monitor_pair(cb_result: object) -> tuple[Concurrence, WaitForPreempt, WaitForPreempt]:
    calls: list[ChildOutcomes] = []

    def on_child_end(outcomes: ChildOutcomes) -> object:
        calls.append(outcomes)
        return cb_result

    cc = Concurrence(outcomes=["done", "preempted"], default_outcome="done",
                     child_termination_cb=cast(Any, on_child_end))
    a = WaitForPreempt(outcomes=["succeeded"])
    b = WaitForPreempt(outcomes=["succeeded"])
    cc.add("A", a)
    cc.add("B", b)
    return cc, a, b


def test_termination_cb_true_preempts_the_others() -> None:
    cc, a, b = monitor_pair(True)
    run = cc.execute_in_thread()
    assert a.entered.wait(5) and b.entered.wait(5)
    a.release("succeeded")
    assert run.result(5) == "done"
    assert not b.preempt_requested()  # serviced
    assert b.executions == 1


def test_termination_cb_list_preempts_only_those() -> None:
    cc = Concurrence(outcomes=["done"], default_outcome="done",
                     child_termination_cb=lambda o: ["B"] if o["A"] else False)
    a, b, c = (WaitForPreempt(outcomes=["succeeded"]) for _ in range(3))
    for label, s in zip("ABC", (a, b, c), strict=True):
        cc.add(label, s)
    events: list[tuple[str | None, str | None]] = []
    b_ended = threading.Event()

    def on_event(e: ContainerEvent) -> None:
        if e.kind == "transition":
            events.append((e.label, e.outcome))
            if e.label == "B":
                b_ended.set()

    cc.add_listener(on_event)
    run = cc.execute_in_thread()
    assert a.entered.wait(5) and b.entered.wait(5) and c.entered.wait(5)
    a.release("succeeded")
    assert b_ended.wait(5)  # B was preempted by the callback...
    assert cc.get_active_states() == ["C"] and not run.done()  # ...C still runs
    c.release("succeeded")
    assert run.result(5) == "done"
    assert sorted(events) == [("A", "succeeded"), ("B", "preempted"), ("C", "succeeded")]


def test_termination_cb_false_waits_for_everyone() -> None:
    cc, a, b = monitor_pair(False)
    a_ended = threading.Event()
    cc.add_listener(lambda e: a_ended.set() if e.label == "A" else None)
    run = cc.execute_in_thread()
    assert a.entered.wait(5) and b.entered.wait(5)
    a.release("succeeded")
    assert a_ended.wait(5)
    assert cc.get_active_states() == ["B"] and not run.done()
    b.release("succeeded")
    assert run.result(5) == "done"
    assert not b.preempt_requested()


@pytest.mark.parametrize("bad", ["B", 3, ["GHOST"]])
def test_termination_cb_bad_answers_are_reported(bad: object) -> None:
    cc, a, b = monitor_pair(bad)
    run = cc.execute_in_thread()
    assert a.entered.wait(5) and b.entered.wait(5)
    a.release("succeeded")
    with pytest.raises(InvalidUserCodeError, match="child_termination_cb of /"):
        run.result(5)


def test_termination_cb_exception_stops_the_others_and_is_raised() -> None:
    def broken(o: ChildOutcomes) -> bool:
        raise KeyError("oops")

    cc = Concurrence(outcomes=["done"], default_outcome="done", child_termination_cb=broken)
    cc.add("A", SucceedState())
    waiter = WaitForPreempt()
    cc.add("B", waiter)
    with pytest.raises(InvalidUserCodeError, match="raised KeyError") as err:
        cc.execute()
    assert isinstance(err.value.__cause__, KeyError)
    assert waiter.executions in (0, 1)


def test_external_preempt_reaches_every_child() -> None:
    cc = Concurrence(outcomes=["done", "preempted"], default_outcome="done")
    a, b = WaitForPreempt(), WaitForPreempt()
    cc.add("A", a)
    cc.add("B", b)
    run = cc.execute_in_thread()
    assert a.entered.wait(5) and b.entered.wait(5)
    assert sorted(cc.get_active_states()) == ["A", "B"]
    run.request_preempt()
    assert run.result(5) == "preempted"  # no map entry, "preempted" declared
    assert not cc.preempt_requested()


def test_external_preempt_without_preempted_outcome_uses_the_default() -> None:
    cc = Concurrence(outcomes=["done"], default_outcome="done")
    a = WaitForPreempt()
    cc.add("A", a)
    run = cc.execute_in_thread()
    assert a.entered.wait(5)
    run.request_preempt()
    assert run.result(5) == "done"


def test_child_error_preempts_the_others_and_is_raised() -> None:
    cc = Concurrence(outcomes=["done"], default_outcome="done")
    waiter = WaitForPreempt()
    cc.add("WAIT", waiter)
    cc.add("BOOM", RaiseState(ValueError("kaput")))
    with pytest.raises(InvalidUserCodeError, match=r"/BOOM \(RaiseState\) raised ValueError: kaput"):
        cc.execute()
    assert not waiter.preempt_requested()
    assert not cc.is_running


def test_children_share_the_container_userdata() -> None:
    def write(key: str) -> CBState:
        def cb(ud: UserDataAccess) -> str:
            ud[key] = key.upper()
            return "succeeded"
        return CBState(cb, outcomes=["succeeded"], output_keys=[key])

    cc = Concurrence(outcomes=["done"], default_outcome="done", output_keys=["a", "b"])
    cc.add("A", write("a"))
    cc.add("B", write("b"))
    sm = StateMachine(outcomes=["done"], output_keys=["a", "b"])
    sm.add("CC", cc)
    assert sm.execute() == "done"
    assert sm.userdata.snapshot() == {"a": "A", "b": "B"}


def test_constructor_checks_the_outcome_policy() -> None:
    with pytest.raises(InvalidStateError, match="default outcome 'nope' is not an outcome"):
        Concurrence(outcomes=["a"], default_outcome="nope")
    with pytest.raises(InvalidStateError, match="outcome_map key 'x' is not an outcome"):
        Concurrence(outcomes=["a"], default_outcome="a", outcome_map={"x": {"A": "s"}})
    with pytest.raises(InvalidStateError, match=r"outcome_map\['a'\] has no conditions"):
        Concurrence(outcomes=["a"], default_outcome="a", outcome_map={"a": {}})
    with pytest.raises(InvalidStateError, match="outcome_cb must be callable"):
        Concurrence(outcomes=["a"], default_outcome="a", outcome_cb=cast(Any, "x"))


def test_outcome_map_wiring_is_checked_before_running() -> None:
    cc = Concurrence(outcomes=["ok", "bad"], default_outcome="bad",
                     outcome_map={"ok": {"A": "succeded", "GHOST": "succeeded"}})
    a = SucceedState()
    cc.add("A", a)
    with pytest.raises(InvalidTransitionError) as err:
        cc.execute()
    text = str(err.value)
    assert "names unknown state 'GHOST'; available states: A" in text
    assert "expects A.succeded, which A does not declare; its outcomes: succeeded" in text
    assert a.executions == 0


def test_set_initial_state_only_accepts_all_children() -> None:
    cc = Concurrence(outcomes=["done"], default_outcome="done")
    cc.add("A", SucceedState())
    cc.add("B", SucceedState())
    cc.set_initial_state(["B", "A"], {"k": 1})
    assert cc.userdata.k == 1
    with pytest.raises(InvalidStateError, match=r"always starts all its states \(A, B\)"):
        cc.set_initial_state(["A"])


def test_structure_shows_the_outcome_map() -> None:
    cc = Concurrence(outcomes=["ok", "bad"], default_outcome="bad",
                     outcome_map={"ok": {"A": "done"}}, child_termination_cb=lambda o: True)
    cc.add("A", FixedOutcome("done"))
    s = cc.get_structure()
    assert [(t.source, t.outcome, t.target) for t in s.transitions] == [("A", "done", "ok")]
    assert s.info == {"default_outcome": "bad", "outcome_cb": False, "child_termination_cb": True}
    assert s.initial_states == ["A"]
