"""What an introspection server reports: status at each event, deferred initial states, the text tree."""

from __future__ import annotations

import threading

import pytest
from zenros.errors import InvalidStateError
from zenros.smach import (
    Concurrence,
    ContainerEvent,
    ContainerStatus,
    StateMachine,
)
from zenros.smach.doubles import SucceedState, WaitForPreempt
from zenros.smach.render import render_tree
from zenros.smach.snapshot import status_at_event


def machine() -> tuple[StateMachine, WaitForPreempt]:
    inner = StateMachine(outcomes=["succeeded", "preempted"])
    wait = WaitForPreempt(outcomes=["succeeded"])
    inner.add("WAIT", wait)
    inner.add("OTHER", SucceedState())
    watch = Concurrence(outcomes=["done", "preempted"], default_outcome="done",
                        child_termination_cb=lambda outcomes: True)
    watch.add("INNER", inner)
    watch.add("SIDE", WaitForPreempt(outcomes=["succeeded"]))
    root = StateMachine(outcomes=["done", "preempted"])
    root.add("FIRST", SucceedState(), transitions={"succeeded": "WATCH"})
    root.add("WATCH", watch)
    root.userdata.laps = 1
    return root, wait


def test_status_at_each_event_shows_what_is_about_to_run() -> None:
    root, wait = machine()
    seen: list[tuple[str, str, list[str], bool]] = []

    def listener(event: ContainerEvent) -> None:
        status = status_at_event(root, event)
        seen.append((event.kind, event.path, status.active_paths, status.running))

    root.add_listener(listener)
    run = root.execute_in_thread()
    assert wait.entered.wait(5)
    run.request_preempt()
    assert run.result(5) == "preempted"
    starts = [s for s in seen if s[0] == "start"]
    assert starts[0] == ("start", "/", ["/FIRST"], True)
    assert ("transition", "/", ["/WATCH"], True) in seen
    assert ("start", "/WATCH", ["/WATCH/INNER", "/WATCH/SIDE"], True) in seen
    assert ("start", "/WATCH/INNER", ["/WATCH/INNER/WAIT", "/WATCH/SIDE"], True) in seen
    assert seen[-1] == ("termination", "/", [], False)


def test_schedule_initial_state_applies_at_once_when_idle_and_next_run_when_running() -> None:
    root, wait = machine()
    assert root.schedule_initial_state(["WATCH"], {"laps": 2}) is True
    assert root.get_initial_states() == ["WATCH"] and root.userdata.laps == 2
    with pytest.raises(InvalidStateError, match="available states: FIRST, WATCH"):
        root.schedule_initial_state(["NOPE"])
    run = root.execute_in_thread()
    assert wait.entered.wait(5)
    assert root.schedule_initial_state(["FIRST"], {"laps": 3}) is False
    assert root.userdata.laps == 2 and root.get_initial_states() == ["FIRST"]
    run.request_preempt()
    assert run.result(5) == "preempted" and root.userdata.laps == 2
    wait.entered.clear()
    entered_with: list[int] = []
    root.add_listener(lambda e: entered_with.append(root.userdata.laps)
                      if e.kind == "start" and e.path == "/" else None)
    run = root.execute_in_thread()
    assert wait.entered.wait(5) and entered_with == [3]
    run.request_preempt()
    assert run.result(5) == "preempted"


def test_render_tree_marks_active_states_and_shows_edges_and_userdata() -> None:
    root, wait = machine()
    idle = render_tree(root.get_structure(), root.get_status(), title="/robot/smach")
    lines = idle.splitlines()
    assert lines[0] == "/robot/smach  StateMachine  idle  (outcomes: done, preempted)"
    assert lines[1] == "    userdata: laps=1"
    assert lines[2] == "|--   FIRST (SucceedState) [initial]  succeeded -> WATCH"
    assert lines[3] == "`--   WATCH (Concurrence)  done -> done, preempted -> preempted"
    assert "    |-- INNER" not in idle and "    |--   INNER (StateMachine)" in idle
    root.userdata.lock = threading.Lock()
    run = root.execute_in_thread()
    assert wait.entered.wait(5)
    busy = render_tree(root.get_structure(), root.get_status())
    marked = [ln.split("*")[1].split("(")[0].strip() for ln in busy.splitlines() if "-- *" in ln]
    assert marked == ["WATCH", "INNER", "WAIT", "SIDE"]
    assert busy.splitlines()[0].startswith("/  StateMachine  running")
    assert "userdata: laps=1, lock=<lock>" in busy
    run.request_preempt()
    assert run.result(5) == "preempted"
    done = render_tree(root.get_structure(), root.get_status())
    assert "finished: preempted" in done.splitlines()[0] and "-- *" not in done
    bare = render_tree(root.get_structure())
    assert "(no status yet)" in bare.splitlines()[0]


def test_render_tree_shortens_long_values() -> None:
    root, _ = machine()
    root.userdata.path = list(range(100))
    status: ContainerStatus = root.get_status()
    text = render_tree(root.get_structure(), status)
    (line,) = [ln for ln in text.splitlines() if "userdata" in ln]
    assert "path=[0,1,2," in line and line.endswith("...") and len(line) < 120
