"""State: declared outcomes and keys, the preemption flag, CBState and cb_interface."""

from __future__ import annotations

import threading
from typing import Any, cast

import pytest
from zenros.errors import InvalidStateError, SmachError
from zenros.smach import CBState, State, UserData, UserDataAccess, cb_interface
from zenros.smach.doubles import WaitForPreempt


class Plain(State):
    def execute(self, userdata: UserDataAccess) -> str:
        return "done"


def test_declarations_keep_order_and_merge_io_keys() -> None:
    s = Plain(outcomes=["b", "a", "b"], input_keys=["x"], output_keys=["y"], io_keys=["z"])
    assert s.outcomes == ("b", "a")
    assert s.input_keys == ("x", "z")
    assert s.output_keys == ("y", "z")
    assert s.path == "/" and s.label is None and s.parent is None


def test_a_bare_string_is_rejected_with_a_hint() -> None:
    with pytest.raises(InvalidStateError, match=r"got the string 'done'; write \['done'\]"):
        Plain(outcomes="done")


def test_a_state_needs_an_outcome() -> None:
    with pytest.raises(InvalidStateError, match="declares no outcome"):
        Plain()


def test_names_must_be_non_empty_strings() -> None:
    with pytest.raises(InvalidStateError, match="non-empty strings"):
        Plain(outcomes=["ok", ""])
    with pytest.raises(InvalidStateError, match="input_keys"):
        Plain(outcomes=["ok"], input_keys=cast(Any, [3]))


def test_errors_are_smach_errors_and_value_errors() -> None:
    with pytest.raises(SmachError):
        Plain()
    with pytest.raises(ValueError):
        Plain()


def test_base_execute_is_abstract() -> None:
    with pytest.raises(NotImplementedError, match="must implement execute"):
        State(outcomes=["x"]).execute(UserData())


def test_preempt_flag_lifecycle() -> None:
    s = Plain(outcomes=["done"])
    assert not s.preempt_requested()
    s.request_preempt()
    assert s.preempt_requested()
    s.service_preempt()
    assert not s.preempt_requested()
    s.request_preempt()
    s.recall_preempt()
    assert not s.preempt_requested()


def test_wait_for_preempt_returns_when_requested_from_another_thread() -> None:
    s = Plain(outcomes=["done"])
    assert s.wait_for_preempt(timeout=0) is False
    t = threading.Thread(target=s.request_preempt)
    t.start()
    assert s.wait_for_preempt(timeout=5) is True
    t.join()


def test_cbstate_passes_userdata_and_extra_arguments() -> None:
    seen = []

    def cb(ud: UserDataAccess, a: int, b: int = 0) -> str:
        seen.append((ud["x"], a, b))
        return "ok"

    s = CBState(cb, args=[1], kwargs={"b": 2}, outcomes=["ok"], input_keys=["x"])
    assert s.execute(UserData({"x": 7})) == "ok"
    assert seen == [(7, 1, 2)]


def test_cb_interface_declares_outcomes_and_keys() -> None:
    @cb_interface(outcomes=["yes"], input_keys=["n"], output_keys=["m"], io_keys=["k"])
    def cb(ud: UserDataAccess) -> str:
        return "yes"

    s = CBState(cb, outcomes=["no"])
    assert set(s.outcomes) == {"no", "yes"}
    assert set(s.input_keys) == {"n", "k"}
    assert set(s.output_keys) == {"m", "k"}


def test_cbstate_needs_a_callable() -> None:
    with pytest.raises(InvalidStateError, match="needs a callable"):
        CBState(cast(Any, "nope"), outcomes=["x"])


def test_repr_names_path_type_and_outcomes() -> None:
    assert repr(WaitForPreempt()) == "</ (WaitForPreempt) outcomes=['preempted']>"
