"""rcl's lifecycle state machine, row by row (specs/rclpy-parity.md, "Lifecycle")."""

from __future__ import annotations

import pytest
from zenros.lifecycle.machine import (
    ACTIVE,
    ERRORPROCESSING,
    FINALIZED,
    INACTIVE,
    TRANSITIONS,
    UNCONFIGURED,
    InvalidTransitionError,
    LifecycleState,
    StateMachine,
    TransitionCallbackReturn,
    TransitionDef,
)
from zenros.msgs.lifecycle_msgs import State, Transition

R = TransitionCallbackReturn
S, F, E = R.SUCCESS, R.FAILURE, R.ERROR

# (from, label, callback result, on_error result or None) -> final state, steps
ROWS = [
    (UNCONFIGURED, "configure", S, INACTIVE),
    (UNCONFIGURED, "configure", F, UNCONFIGURED),
    (INACTIVE, "cleanup", S, UNCONFIGURED),
    (INACTIVE, "cleanup", F, INACTIVE),
    (INACTIVE, "activate", S, ACTIVE),
    (INACTIVE, "activate", F, INACTIVE),
    (ACTIVE, "deactivate", S, INACTIVE),
    (ACTIVE, "deactivate", F, ACTIVE),
    (UNCONFIGURED, "shutdown", S, FINALIZED),
    (INACTIVE, "shutdown", F, FINALIZED),
    (ACTIVE, "shutdown", S, FINALIZED),
    (ACTIVE, "shutdown", F, FINALIZED),
]


def _machine_at(state: int) -> StateMachine:
    m = StateMachine()
    m._state = state  # the rows start anywhere
    return m


def _run(m: StateMachine, label: str, ret: R, on_error: R = S) -> tuple[R, list[TransitionDef],
                                                                        list[tuple[int, str]]]:
    steps: list[TransitionDef] = []
    calls: list[tuple[int, str]] = []

    def call(state_id: int, starting: LifecycleState) -> R:
        calls.append((state_id, starting.label))
        return on_error if state_id == ERRORPROCESSING else ret

    out = m.trigger(m.find(label=label), call, steps.append)
    return out, steps, calls


@pytest.mark.parametrize(("start", "label", "ret", "goal"), ROWS)
def test_each_row_of_the_table(start: int, label: str, ret: R, goal: int) -> None:
    m = _machine_at(start)
    out, steps, calls = _run(m, label, ret)
    assert out is ret
    assert m.state_id == goal
    assert len(steps) == 2  # the request, then its outcome
    assert steps[0].label == label and steps[0].start == start
    assert steps[1].start == steps[0].goal and steps[1].goal == goal
    assert steps[1].label == ret.to_label()
    assert calls == [(steps[0].goal, LifecycleState.of(start).label)]  # the starting state


@pytest.mark.parametrize(("start", "label"), [
    (UNCONFIGURED, "configure"), (INACTIVE, "cleanup"), (INACTIVE, "activate"),
    (ACTIVE, "deactivate"), (UNCONFIGURED, "shutdown"), (INACTIVE, "shutdown"),
    (ACTIVE, "shutdown")])
@pytest.mark.parametrize(("on_error", "goal"), [(S, UNCONFIGURED), (F, FINALIZED),
                                                (E, FINALIZED)])
def test_error_goes_through_errorprocessing(start: int, label: str, on_error: R,
                                            goal: int) -> None:
    m = _machine_at(start)
    out, steps, calls = _run(m, label, E, on_error)
    assert out is E
    assert m.state_id == goal
    assert [s.goal for s in steps] == [steps[0].goal, ERRORPROCESSING, goal]  # three events
    assert steps[2].id == {S: 60, F: 61, E: 62}[on_error]
    assert calls[-1] == (ERRORPROCESSING, LifecycleState.of(start).label)


def test_ids_and_labels_are_lifecycle_msgs() -> None:
    by_id = {t.id: t for t in TRANSITIONS}
    assert by_id[Transition.TRANSITION_CONFIGURE].label == "configure"
    assert by_id[Transition.TRANSITION_ACTIVE_SHUTDOWN].start == State.PRIMARY_STATE_ACTIVE
    assert by_id[Transition.TRANSITION_ON_ACTIVATE_ERROR].goal == \
        State.TRANSITION_STATE_ERRORPROCESSING
    assert by_id[Transition.TRANSITION_ON_ERROR_SUCCESS].goal == State.PRIMARY_STATE_UNCONFIGURED
    assert R.SUCCESS == Transition.TRANSITION_CALLBACK_SUCCESS
    assert R.ERROR == Transition.TRANSITION_CALLBACK_ERROR
    assert len(by_id) == len(TRANSITIONS) == 25


def test_label_beats_id() -> None:
    m = StateMachine()
    # id 3 (activate) is not valid from unconfigured, the label is: the label wins
    assert m.find(Transition.TRANSITION_ACTIVATE, "configure").label == "configure"
    assert m.find(Transition.TRANSITION_CONFIGURE).label == "configure"
    assert m.find(label="shutdown").id == Transition.TRANSITION_UNCONFIGURED_SHUTDOWN
    with pytest.raises(InvalidTransitionError, match="'activate'"):
        m.find(Transition.TRANSITION_CONFIGURE, "activate")


@pytest.mark.parametrize(("state", "label"), [
    (UNCONFIGURED, "activate"), (UNCONFIGURED, "cleanup"), (INACTIVE, "configure"),
    (INACTIVE, "deactivate"), (ACTIVE, "activate"), (ACTIVE, "cleanup"),
    (FINALIZED, "configure"), (FINALIZED, "shutdown"), (UNCONFIGURED, "transition_success"),
    (UNCONFIGURED, "nonsense")])
def test_invalid_transitions_are_refused(state: int, label: str) -> None:
    m = _machine_at(state)
    with pytest.raises(InvalidTransitionError, match="valid:"):
        m.find(label=label)
    assert m.state_id == state


def test_no_transition_is_requested_while_one_runs() -> None:
    m = StateMachine()
    seen: list[str] = []

    def call(state_id: int, starting: LifecycleState) -> R:
        with pytest.raises(InvalidTransitionError, match="in progress"):
            m.find(label="transition_success")
        seen.append(m.state.label)
        return S

    m.trigger(m.find(label="configure"), call, lambda t: None)
    assert seen == ["configuring"]
    assert [t.label for t in m.available()] == ["cleanup", "activate", "shutdown"]
