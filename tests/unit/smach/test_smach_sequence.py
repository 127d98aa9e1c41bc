"""Sequence: states linked in insertion order by the connector outcome."""

from __future__ import annotations

from typing import cast

import pytest
from zenros.errors import InvalidStateError, InvalidTransitionError
from zenros.smach import CBState, Sequence, UserDataAccess
from zenros.smach.doubles import FailState, FixedOutcome, SucceedState


def recorder(log: list[str], name: str, outcome: str = "succeeded") -> CBState:
    def cb(ud: UserDataAccess) -> str:
        log.append(name)
        return outcome

    return CBState(cb, outcomes=["succeeded", "aborted"])


def test_runs_in_insertion_order() -> None:
    log: list[str] = []
    seq = Sequence(outcomes=["succeeded", "aborted"], connector_outcome="succeeded")
    for name in "ABC":
        seq.add(name, recorder(log, name))
    assert seq.execute() == "succeeded"
    assert log == ["A", "B", "C"]
    assert seq.connector_outcome == "succeeded"


def test_other_outcomes_fall_through_and_stop_the_sequence() -> None:
    log: list[str] = []
    seq = Sequence(outcomes=["succeeded", "aborted"], connector_outcome="succeeded")
    seq.add("A", recorder(log, "A"))
    seq.add("B", recorder(log, "B", "aborted"))
    seq.add("C", recorder(log, "C"))
    assert seq.execute() == "aborted"
    assert log == ["A", "B"]


def test_explicit_connector_transition_overrides_the_link() -> None:
    seq = Sequence(outcomes=["succeeded", "aborted"], connector_outcome="succeeded")
    seq.add("A", SucceedState(outcomes=["aborted"]), transitions={"succeeded": "C"})
    seq.add("B", FailState(outcomes=["succeeded"]))
    seq.add("C", SucceedState(outcomes=["aborted"]))
    assert seq.execute() == "succeeded"
    assert cast(FailState, seq["B"]).executions == 0


def test_every_state_needs_the_connector_outcome() -> None:
    seq = Sequence(outcomes=["succeeded"], connector_outcome="succeeded")
    with pytest.raises(InvalidStateError, match="lacks the connector outcome 'succeeded'; its"
                       " outcomes: done"):
        seq.add("A", FixedOutcome("done"))


def test_last_connector_needs_a_container_outcome() -> None:
    seq = Sequence(outcomes=["finished"], connector_outcome="next")
    seq.add("A", FixedOutcome("next"))
    with pytest.raises(InvalidTransitionError, match="outcome A.next in / is not connected"):
        seq.check()
    seq2 = Sequence(outcomes=["finished"], connector_outcome="next")
    seq2.add("A", FixedOutcome("next"), transitions={"next": "finished"})
    assert seq2.execute() == "finished"


def test_bad_connector() -> None:
    with pytest.raises(InvalidStateError, match="connector_outcome must be an outcome name"):
        Sequence(outcomes=["x"], connector_outcome="")


def test_structure_records_the_connector() -> None:
    seq = Sequence(outcomes=["succeeded"], connector_outcome="succeeded")
    seq.add("A", SucceedState())
    seq.add("B", SucceedState())
    s = seq.get_structure()
    assert s.type == "Sequence" and s.info == {"connector_outcome": "succeeded"}
    assert [(t.source, t.outcome, t.target, t.implicit) for t in s.transitions] == [
        ("A", "succeeded", "B", False), ("B", "succeeded", "succeeded", True)]
