"""Introspection data: structure, status, events and listeners, as a Zenoh server would use them."""

from __future__ import annotations

import logging
import threading
from typing import Any, cast

import pytest
from zenros.codec import codec_for
from zenros.errors import InvalidStateError, SmachError
from zenros.smach import (
    CBState,
    Concurrence,
    ContainerEvent,
    ContainerStatus,
    Iterator,
    StateMachine,
    StateStructure,
    UserDataAccess,
)
from zenros.smach.doubles import FailState, SucceedState, WaitForPreempt


def patrol() -> tuple[StateMachine, WaitForPreempt]:
    nav = StateMachine(outcomes=["succeeded", "aborted", "preempted"], input_keys=["goal"])
    wait = WaitForPreempt(outcomes=["succeeded", "aborted"], input_keys=["target"])
    nav.add("GO", wait, remapping={"target": "goal"})
    root = StateMachine(outcomes=["done", "failed", "preempted"])
    root.userdata.goal = {"x": 1.0, "y": 2.0}
    root.userdata.lock = threading.Lock()
    root.add("NAV", nav, transitions={"succeeded": "DOCK", "aborted": "failed"})
    root.add("DOCK", SucceedState(outcomes=["aborted"]),
             transitions={"succeeded": "done", "aborted": "failed"})
    return root, wait


def test_structure_is_recursive_and_complete() -> None:
    root, _ = patrol()
    s = root.get_structure()
    assert (s.path, s.label, s.type, s.is_container) == ("/", "", "StateMachine", True)
    assert s.outcomes == ["done", "failed", "preempted"]
    assert s.initial_states == ["NAV"]
    assert [(t.source, t.outcome, t.target, t.implicit) for t in s.transitions] == [
        ("NAV", "succeeded", "DOCK", False),
        ("NAV", "aborted", "failed", False),
        ("NAV", "preempted", "preempted", True),
        ("DOCK", "aborted", "failed", False),
        ("DOCK", "succeeded", "done", False),
    ]
    nav, dock = s.children
    assert (nav.path, nav.is_container, nav.input_keys) == ("/NAV", True, ["goal"])
    assert (dock.path, dock.is_container, dock.children) == ("/DOCK", False, [])
    go = nav.children[0]
    assert (go.path, go.type, go.remapping) == ("/NAV/GO", "WaitForPreempt", {"target": "goal"})


def test_structure_and_status_encode_as_messages() -> None:
    root, _ = patrol()
    for value in (root.get_structure(), root.get_status()):
        codec = codec_for(type(value))
        assert codec.decode(codec.encode(value)) == value
    assert codec_for(StateStructure).type_name == "zenros_smach/StateStructure"


def test_status_while_running_shows_the_active_path_and_userdata() -> None:
    root, wait = patrol()
    run = root.execute_in_thread()
    assert wait.entered.wait(5)
    status = root.get_status()
    assert status.running and status.active_states == ["NAV"]
    assert status.active_paths == ["/NAV/GO"]
    assert status.userdata == {"goal": {"x": 1.0, "y": 2.0}}
    assert status.unserializable == {"lock": "lock"}
    (nav,) = status.children
    assert (nav.path, nav.active_states, nav.userdata) == ("/NAV", ["GO"], {"goal": {"x": 1.0, "y": 2.0}})
    wait.release("succeeded")
    assert run.result(5) == "done"
    after = root.get_status()
    assert not after.running and after.active_paths == [] and after.last_outcome == "done"


def test_listener_hears_nested_events_in_order() -> None:
    root, wait = patrol()
    events: list[ContainerEvent] = []
    root.add_listener(events.append)
    wait.release("succeeded")
    assert root.execute() == "done"
    summary = [(e.kind, e.path, e.label, e.outcome, e.target, e.active_states) for e in events]
    assert summary == [
        ("start", "/", None, None, None, ["NAV"]),
        ("start", "/NAV", None, None, None, ["GO"]),
        ("transition", "/NAV", "GO", "succeeded", "succeeded", []),
        ("termination", "/NAV", None, "succeeded", None, []),
        ("transition", "/", "NAV", "succeeded", "DOCK", ["DOCK"]),
        ("transition", "/", "DOCK", "succeeded", "done", []),
        ("termination", "/", None, "done", None, []),
    ]


def test_termination_event_carries_errors() -> None:
    sm = StateMachine(outcomes=["x"])
    sm.add("BAD", CBState(lambda ud: "nope", outcomes=["x"]))
    events: list[ContainerEvent] = []
    sm.add_listener(events.append)
    with pytest.raises(SmachError):
        sm.execute()
    assert events[-1].kind == "termination" and "returned 'nope'" in (events[-1].error or "")


def test_a_failing_listener_is_logged_and_the_machine_goes_on(
    caplog: pytest.LogCaptureFixture,
) -> None:
    def broken(event: ContainerEvent) -> None:
        raise RuntimeError("listener bug")

    sm = StateMachine(outcomes=["succeeded"])
    sm.add("A", SucceedState())
    got: list[str] = []
    sm.add_listener(broken)
    sm.add_listener(lambda e: got.append(e.kind))
    with caplog.at_level(logging.ERROR, logger="zenros.smach"):
        assert sm.execute() == "succeeded"
    assert got == ["start", "transition", "termination"]
    assert "listener" in caplog.text and "listener bug" in caplog.text


def test_removed_listeners_hear_nothing() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    sm.add("A", SucceedState())
    got: list[ContainerEvent] = []
    remove = sm.add_listener(got.append)
    remove()
    remove()  # idempotent
    sm.execute()
    assert got == []


def test_iterator_and_concurrence_events() -> None:
    it = Iterator(outcomes=["done"], it=[1, 2], exhausted_outcome="done")
    it.set_contained_state("S", SucceedState(), loop_outcomes=["succeeded"])
    cc = Concurrence(outcomes=["ok", "bad"], default_outcome="bad",
                     outcome_map={"ok": {"LOOP": "done", "F": "aborted"}})
    cc.add("LOOP", it)
    cc.add("F", FailState())
    events: list[ContainerEvent] = []
    cc.add_listener(events.append)
    assert cc.execute() == "ok"
    loop = [(e.kind, e.label, e.target) for e in events if e.path == "/LOOP"]
    assert loop == [("start", None, None), ("transition", "S", "S"), ("transition", "S", "S"),
                    ("termination", None, None)]
    top = [(e.kind, e.label, e.outcome) for e in events if e.path == "/"]
    assert top[0] == ("start", None, None) and top[-1] == ("termination", None, "ok")
    assert sorted(t[1] or "" for t in top[1:-1]) == ["F", "LOOP"]


def test_find_and_set_initial_state_of_a_nested_container() -> None:
    root, _ = patrol()
    nav = root.find("/NAV")
    assert isinstance(nav, StateMachine)
    assert root.find("NAV/GO").path == "/NAV/GO"
    assert root.find("") is root
    with pytest.raises(InvalidStateError, match="no state 'NAVV' in /; its states: DOCK, NAV"):
        root.find("/NAVV/GO")
    with pytest.raises(InvalidStateError, match="is not a container"):
        root.find("/DOCK/X")
    with pytest.raises(InvalidStateError, match="no state 'Q' in /NAV; its states: GO"):
        cast(Any, root["NAV"])["Q"]
    nav.set_initial_state(["GO"], {"extra": 5})
    assert nav.get_status().userdata["extra"] == 5


def test_introspection_can_resume_a_machine_mid_way() -> None:
    """What an introspection tool or the task manager does to restart at a saved state."""
    log: list[str] = []

    def step(name: str) -> CBState:
        def cb(ud: UserDataAccess) -> str:
            log.append(f"{name}:{ud.progress}")
            return "succeeded"
        return CBState(cb, outcomes=["succeeded"], input_keys=["progress"])

    sm = StateMachine(outcomes=["succeeded"])
    sm.add("ONE", step("ONE"), transitions={"succeeded": "TWO"})
    sm.add("TWO", step("TWO"), transitions={"succeeded": "THREE"})
    sm.add("THREE", step("THREE"))
    saved = ContainerStatus(path="/", type="StateMachine", running=False, initial_states=[],
                            active_states=["TWO"], active_paths=["/TWO"], userdata={"progress": 7})
    sm.set_initial_state(saved.active_states, saved.userdata)
    assert sm.execute() == "succeeded"
    assert log == ["TWO:7", "THREE:7"]
