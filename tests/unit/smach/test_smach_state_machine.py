"""StateMachine: transitions, nesting, userdata flow, wiring checks and runtime errors."""

from __future__ import annotations

from typing import Any, cast

import pytest
from zenros.errors import (
    InvalidStateError,
    InvalidTransitionError,
    InvalidUserCodeError,
    SmachError,
    UserDataError,
)
from zenros.smach import CBState, State, StateMachine, UserData, UserDataAccess
from zenros.smach.doubles import (
    FailState,
    FixedOutcome,
    OutcomeQueue,
    RaiseState,
    SucceedState,
    WaitForPreempt,
)


class Foo(State):
    """The smach tutorial state: counts up in userdata, leaves after three rounds."""

    def __init__(self) -> None:
        super().__init__(["outcome1", "outcome2"], input_keys=["foo_in"], output_keys=["foo_out"])

    def execute(self, userdata: UserDataAccess) -> str:
        count = userdata.foo_in
        userdata.foo_out = count + 1
        return "outcome1" if count < 3 else "outcome2"


class Bar(State):
    def __init__(self) -> None:
        super().__init__(["outcome1"], input_keys=["bar_in"])
        self.seen: list[int] = []

    def execute(self, userdata: UserDataAccess) -> str:
        self.seen.append(userdata.bar_in)
        return "outcome1"


def tutorial_machine() -> tuple[StateMachine, Bar]:
    sm = StateMachine(outcomes=["done", "failed"])
    sm.userdata.counter = 0
    bar = Bar()
    sm.add("FOO", Foo(), transitions={"outcome1": "BAR", "outcome2": "done"},
           remapping={"foo_in": "counter", "foo_out": "counter"})
    sm.add("BAR", bar, transitions={"outcome1": "FOO"}, remapping={"bar_in": "counter"})
    return sm, bar


def test_tutorial_machine_loops_then_ends() -> None:
    sm, bar = tutorial_machine()
    assert sm.execute() == "done"
    assert bar.seen == [1, 2, 3]
    assert sm.userdata.counter == 4
    assert not sm.is_running


def test_a_machine_can_run_again() -> None:
    sm, bar = tutorial_machine()
    sm.execute()
    sm.userdata.counter = 2
    assert sm.execute() == "done"
    assert bar.seen == [1, 2, 3, 3]


def test_add_returns_the_state_and_first_state_is_initial() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    s = SucceedState()
    assert sm.add("A", s) is s
    sm.add("B", SucceedState())
    assert sm.get_initial_states() == ["A"]
    assert sm["A"] is s and list(sm.children) == ["A", "B"]
    assert s.path == "/A" and s.label == "A" and s.parent is sm


def test_unmapped_outcome_falls_through_to_the_same_named_machine_outcome() -> None:
    sm = StateMachine(outcomes=["succeeded", "aborted"])
    sm.add("A", SucceedState(outcomes=["aborted"]))
    assert sm.execute() == "succeeded"


def test_explicit_transition_overrides_fall_through() -> None:
    sm = StateMachine(outcomes=["succeeded", "aborted"])
    sm.add("A", SucceedState(), transitions={"succeeded": "B"})
    sm.add("B", FailState())
    assert sm.execute() == "aborted"


def test_nested_machines_pass_keys_through_remapping() -> None:
    inner = StateMachine(outcomes=["done"], input_keys=["x"], output_keys=["y"])

    def double(ud: UserDataAccess) -> str:
        ud.y = ud.x * 2
        return "done"

    inner.add("DOUBLE", CBState(double, outcomes=["done"], input_keys=["x"], output_keys=["y"]))
    outer = StateMachine(outcomes=["finished"], input_keys=["start"], output_keys=["result"])
    outer.add("INNER", inner, transitions={"done": "finished"},
              remapping={"x": "start", "y": "result"})
    parent = UserData({"start": 21})
    assert outer.execute(parent) == "finished"
    assert parent["result"] == 42
    assert inner.path == "/INNER" and inner["DOUBLE"].path == "/INNER/DOUBLE"


def test_root_input_keys_must_be_set_when_run_without_userdata() -> None:
    sm = StateMachine(outcomes=["succeeded"], input_keys=["goal"])
    sm.add("A", SucceedState())
    with pytest.raises(UserDataError, match=r"needs input key 'goal': pass it in execute"):
        sm.execute()
    sm.userdata.goal = 1
    assert sm.execute() == "succeeded"


def test_missing_input_key_in_parent_userdata_names_the_container() -> None:
    sm = StateMachine(outcomes=["succeeded"], input_keys=["goal"])
    sm.add("A", SucceedState())
    with pytest.raises(UserDataError, match=r"/ \(StateMachine\) needs input key 'goal', which the"
                       r" userdata passed to execute\(\) lacks; set keys: other"):
        sm.execute(UserData({"other": 1}))


def test_nested_container_missing_input_names_the_nested_path() -> None:
    inner = StateMachine(outcomes=["succeeded"], input_keys=["goal"])
    inner.add("A", SucceedState())
    outer = StateMachine(outcomes=["succeeded"])
    # declares "goal" as output (so the wiring check passes) but never writes it
    outer.add("LAZY", CBState(lambda ud: "succeeded", outcomes=["succeeded"],
                              output_keys=["goal"]), transitions={"succeeded": "SUB"})
    outer.add("SUB", inner)
    with pytest.raises(UserDataError, match=r"state /SUB \(StateMachine\) read input key 'goal',"
                       r" which is not set"):
        outer.execute()


def test_output_keys_not_written_are_skipped() -> None:
    sm = StateMachine(outcomes=["succeeded"], output_keys=["maybe"])
    sm.add("A", CBState(lambda ud: "succeeded", outcomes=["succeeded"], output_keys=["maybe"]))
    parent = UserData()
    assert sm.execute(parent) == "succeeded"
    assert "maybe" not in parent


# ---------------------------------------------------------------- wiring checked at add()


def test_duplicate_label_lists_the_labels_in_use() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    sm.add("A", SucceedState())
    with pytest.raises(InvalidStateError, match="duplicate label 'A' in /; labels in use: A"):
        sm.add("A", SucceedState())


@pytest.mark.parametrize("label", ["", "A/B", 3])
def test_bad_labels(label: object) -> None:
    sm = StateMachine(outcomes=["succeeded"])
    with pytest.raises(InvalidStateError, match="non-empty string without '/'"):
        sm.add(cast(Any, label), SucceedState())


def test_label_equal_to_a_machine_outcome_is_ambiguous() -> None:
    sm = StateMachine(outcomes=["succeeded", "done"])
    with pytest.raises(InvalidStateError, match="'done' in / is also an outcome"):
        sm.add("done", SucceedState())


def test_transition_from_an_undeclared_outcome_lists_the_state_outcomes() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    with pytest.raises(InvalidTransitionError, match="use outcomes sucess, which SucceedState does"
                       " not declare; its outcomes: succeeded"):
        sm.add("A", SucceedState(), transitions={"sucess": "succeeded"})
    assert not sm.children  # nothing was added


def test_transition_target_must_be_a_name() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    with pytest.raises(InvalidTransitionError, match="must name a state or an outcome, got None"):
        sm.add("A", SucceedState(), transitions=cast(Any, {"succeeded": None}))


def test_remapping_of_undeclared_keys_lists_the_state_keys() -> None:
    sm = StateMachine(outcomes=["outcome1"])
    with pytest.raises(InvalidStateError, match="names keys the state does not declare: bar_inn;"
                       " its keys: bar_in"):
        sm.add("BAR", Bar(), remapping={"bar_inn": "counter"})


def test_a_state_instance_lives_in_one_place() -> None:
    s = SucceedState()
    a = StateMachine(outcomes=["succeeded"])
    a.add("X", s)
    with pytest.raises(InvalidStateError, match="already /X; create a new instance"):
        a.add("Y", s)
    b = StateMachine(outcomes=["succeeded"])
    with pytest.raises(InvalidStateError, match="already /X"):
        b.add("X", s)


def test_a_container_cannot_contain_itself() -> None:
    outer = StateMachine(outcomes=["succeeded"])
    inner = StateMachine(outcomes=["succeeded"])
    outer.add("IN", inner)
    with pytest.raises(InvalidStateError, match="inside itself"):
        inner.add("LOOP", outer)
    with pytest.raises(InvalidStateError, match="inside itself"):
        outer.add("ME", outer)


def test_only_states_can_be_added() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    with pytest.raises(InvalidStateError, match="expected a State, got function"):
        sm.add("F", cast(Any, lambda ud: "x"))


# ---------------------------------------------------------------- wiring checked before running


def test_unknown_target_lists_states_and_outcomes_and_nothing_runs() -> None:
    sm = StateMachine(outcomes=["done", "failed"])
    foo = FixedOutcome("outcome1", outcomes=["outcome2"])
    sm.add("FOO", foo, transitions={"outcome1": "BAZ", "outcome2": "done"})
    sm.add("BAR", FixedOutcome("outcome1"), transitions={"outcome1": "FOO"})
    msg = ("unknown state 'BAZ' in transition FOO.outcome1 of /; available states: BAR, FOO;"
           " container outcomes: done, failed")
    with pytest.raises(InvalidTransitionError, match=msg):
        sm.check()
    with pytest.raises(InvalidTransitionError, match="BAZ"):
        sm.execute()
    assert foo.executions == 0


def test_unconnected_outcome_is_reported() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    sm.add("A", SucceedState(outcomes=["aborted"]))
    with pytest.raises(InvalidTransitionError, match="outcome A.aborted in / is not connected;"
                       " available states: A; container outcomes: succeeded"):
        sm.check()


def test_all_problems_are_listed_at_once() -> None:
    sm = StateMachine(outcomes=["done"])
    sm.add("A", FixedOutcome("x", outcomes=["y"]), transitions={"x": "NOPE"})
    with pytest.raises(InvalidTransitionError) as err:
        sm.check()
    assert "NOPE" in str(err.value) and "A.y" in str(err.value)


def test_missing_key_lists_the_available_keys() -> None:
    sm = StateMachine(outcomes=["outcome1"], input_keys=["speed"])
    sm.add("BAR", Bar(), remapping={"bar_in": "counter"})
    with pytest.raises(InvalidStateError, match=r"/BAR \(Bar\) reads key 'bar_in' \(remapped to"
                       r" 'counter'\), which nothing in / provides; available keys: speed"):
        sm.check()


def test_keys_written_by_sibling_states_or_preset_count_as_provided() -> None:
    sm = StateMachine(outcomes=["outcome1"])
    sm.add("BAR", Bar(), remapping={"bar_in": "counter"})
    sm.userdata.counter = 1
    sm.check()
    sm2 = StateMachine(outcomes=["succeeded"])
    sm2.add("W", CBState(lambda ud: "succeeded", outcomes=["succeeded"], output_keys=["n"]),
            transitions={"succeeded": "R"})
    sm2.add("R", CBState(lambda ud: "succeeded", outcomes=["succeeded"], input_keys=["n"]))
    sm2.check()


def test_container_output_keys_must_be_written_by_someone() -> None:
    sm = StateMachine(outcomes=["succeeded"], output_keys=["result"])
    sm.add("A", SucceedState())
    with pytest.raises(InvalidStateError, match="output key 'result' of / is never written"):
        sm.check()


def test_an_empty_machine_is_rejected() -> None:
    with pytest.raises(InvalidStateError, match="/ has no states"):
        StateMachine(outcomes=["done"]).execute()


def test_nested_problems_name_the_nested_path() -> None:
    inner = StateMachine(outcomes=["done"])
    inner.add("X", FixedOutcome("done"), transitions={"done": "GHOST"})
    outer = StateMachine(outcomes=["done"])
    outer.add("SUB", inner)
    with pytest.raises(InvalidTransitionError, match="unknown state 'GHOST' in transition X.done"
                       " of /SUB"):
        outer.check()


# ---------------------------------------------------------------- runtime errors


def test_undeclared_key_read_at_runtime_names_state_and_key() -> None:
    def sneaky(ud: UserDataAccess) -> str:
        ud["secret"]
        return "done"

    sm = StateMachine(outcomes=["done"])
    sm.userdata.secret = 1
    sm.add("SNEAK", CBState(sneaky, outcomes=["done"]))
    with pytest.raises(UserDataError, match=r"state /SNEAK \(CBState\) read userdata key 'secret'"):
        sm.execute()


def test_input_only_key_write_at_runtime_names_state_and_key() -> None:
    def writer(ud: UserDataAccess) -> str:
        ud.goal = 2
        return "done"

    sm = StateMachine(outcomes=["done"])
    sm.userdata.goal = 1
    sm.add("W", CBState(writer, outcomes=["done"], input_keys=["goal"]))
    with pytest.raises(UserDataError, match=r"state /W \(CBState\) wrote userdata key 'goal'"):
        sm.execute()
    assert sm.userdata.goal == 1


def test_undeclared_outcome_at_runtime() -> None:
    sm = StateMachine(outcomes=["done"])
    sm.add("A", CBState(lambda ud: "oops", outcomes=["done"]))
    with pytest.raises(InvalidUserCodeError, match=r"/A \(CBState\) returned 'oops', which is not"
                       r" a declared outcome; its outcomes: done"):
        sm.execute()
    assert not sm.is_running and sm.get_active_states() == []


def test_exceptions_in_states_are_wrapped_with_the_path() -> None:
    inner = StateMachine(outcomes=["succeeded"])
    inner.add("BOOM", RaiseState(ValueError("bad goal")))
    outer = StateMachine(outcomes=["succeeded"])
    outer.add("SUB", inner)
    with pytest.raises(InvalidUserCodeError, match=r"/SUB/BOOM \(RaiseState\) raised ValueError:"
                       r" bad goal") as err:
        outer.execute()
    assert isinstance(err.value.__cause__, ValueError)


def test_set_initial_state_and_userdata() -> None:
    sm = StateMachine(outcomes=["succeeded", "aborted"])
    sm.add("A", SucceedState(), transitions={"succeeded": "B"})
    sm.add("B", CBState(lambda ud: "aborted" if ud.flag else "succeeded",
                        outcomes=["succeeded", "aborted"], input_keys=["flag"]))
    sm.set_initial_state(["B"], {"flag": True})
    assert sm.get_initial_states() == ["B"]
    assert sm.execute() == "aborted"
    assert cast(SucceedState, sm["A"]).executions == 0
    sm.set_initial_state([])  # keeps B
    assert sm.get_initial_states() == ["B"]


def test_set_initial_state_rejects_unknown_or_several_labels() -> None:
    sm = StateMachine(outcomes=["succeeded"])
    sm.add("A", SucceedState())
    with pytest.raises(InvalidStateError, match="unknown initial state 'Z' for /; available"
                       " states: A"):
        sm.set_initial_state(["Z"])
    with pytest.raises(InvalidStateError, match="starts in one state"):
        sm.set_initial_state(["A", "A2"])


def test_running_machine_refuses_changes_and_a_second_run() -> None:
    sm = StateMachine(outcomes=["preempted"])
    wait = WaitForPreempt()
    sm.add("WAIT", wait)
    run = sm.execute_in_thread()
    assert wait.entered.wait(5)
    with pytest.raises(SmachError, match="already running"):
        sm.execute()
    with pytest.raises(SmachError, match="while the machine is running"):
        sm.add("MORE", SucceedState())
    with pytest.raises(SmachError, match="while it runs"):
        sm.set_initial_state(["WAIT"])
    run.request_preempt()
    assert run.result(5) == "preempted"


def test_outcome_queue_drives_a_retry_loop() -> None:
    sm = StateMachine(outcomes=["succeeded", "aborted"])
    flaky = OutcomeQueue(["aborted", "aborted", "succeeded"])
    sm.add("TRY", flaky, transitions={"aborted": "TRY"})
    assert sm.execute() == "succeeded"
    assert flaky.executions == 3
