"""Goal scheduling policies and the goal state machine, driven step by step (no Zenoh)."""

from __future__ import annotations

import pytest
from zenros.action.policies import GoalPolicy, Plan, Scheduler
from zenros.action.states import GoalEvent, transition
from zenros.action.types import GoalStatus
from zenros.errors import GoalStateError


def sched(spec: str) -> Scheduler[str]:
    return Scheduler(GoalPolicy.parse(spec))


# ------------------------------------------------------------------ parsing


@pytest.mark.parametrize(
    ("spec", "kind", "limit", "max_waiting"),
    [
        ("simple", "simple", 1, None),
        ("queue", "queue", 1, None),
        ("queue:3", "queue", 1, 3),
        ("reject_if_busy", "reject_if_busy", 1, None),
        ("parallel", "parallel", None, None),
        ("parallel:4", "parallel", 4, None),
    ],
)
def test_parse_policy_names(spec: str, kind: str, limit: int | None,
                            max_waiting: int | None) -> None:
    p = GoalPolicy.parse(spec)
    assert (p.kind, p.limit, p.max_waiting) == (kind, limit, max_waiting)
    assert str(p) == spec
    assert GoalPolicy.parse(p) is p


@pytest.mark.parametrize(
    ("spec", "needle"),
    [
        ("fifo", "unknown goal policy 'fifo'; valid: simple, queue, reject_if_busy, parallel"),
        ("parallel:x", "expected parallel:<integer>"),
        ("parallel:0", "limit must be >= 1"),
        ("simple:2", "takes no argument"),
        ("queue:-1", "max_waiting must be >= 0"),
    ],
)
def test_bad_policy_names_say_what_is_valid(spec: str, needle: str) -> None:
    with pytest.raises(ValueError) as err:
        GoalPolicy.parse(spec)
    assert needle in str(err.value)


def test_single_goal_policies_refuse_a_limit() -> None:
    with pytest.raises(ValueError, match="one goal at a time"):
        GoalPolicy("queue", limit=2)


# ------------------------------------------------------------------ simple


def test_simple_new_goal_preempts_the_running_one_and_starts_after_it() -> None:
    s = sched("simple")
    assert s.offer("a") == Plan(start=("a",))
    assert s.offer("b") == Plan(preempt=("a",))  # a is asked to cancel; b waits for it
    assert s.running == ["a"] and list(s.waiting) == ["b"]
    assert s.finish("a") == Plan(start=("b",))
    assert s.running == ["b"] and not s.waiting


def test_simple_a_newer_goal_replaces_the_waiting_one() -> None:
    s = sched("simple")
    s.offer("a")
    s.offer("b")
    # a is already preempted: not asked again; b never ran and is dropped (ends canceled)
    assert s.offer("c") == Plan(drop=("b",))
    assert s.finish("a") == Plan(start=("c",))
    assert s.offer("d") == Plan(preempt=("c",))


def test_simple_idle_server_starts_at_once() -> None:
    s = sched("simple")
    s.offer("a")
    s.finish("a")
    assert s.offer("b") == Plan(start=("b",))


# ------------------------------------------------------------------ queue


def test_queue_runs_goals_one_at_a_time_in_arrival_order() -> None:
    s = sched("queue")
    assert s.offer("a") == Plan(start=("a",))
    assert s.offer("b") == Plan()
    assert s.offer("c") == Plan()
    assert s.finish("a") == Plan(start=("b",))
    assert s.finish("b") == Plan(start=("c",))
    assert s.finish("c") == Plan()
    assert not s.busy


def test_bounded_queue_rejects_when_full() -> None:
    s = sched("queue:1")
    s.offer("a")
    s.offer("b")
    plan = s.offer("c")
    assert plan.reject == "queue full: 1 goals waiting (policy queue:1)"
    assert list(s.waiting) == ["b"]


def test_withdraw_removes_only_waiting_goals() -> None:
    s = sched("queue")
    s.offer("a")
    s.offer("b")
    s.offer("c")
    assert s.withdraw("b")
    assert not s.withdraw("a")  # running: must be canceled by its execute callback
    assert not s.withdraw("zz")
    assert s.finish("a") == Plan(start=("c",))


# ------------------------------------------------------------------ reject_if_busy


def test_reject_if_busy_rejects_while_a_goal_runs() -> None:
    s = sched("reject_if_busy")
    assert s.offer("a") == Plan(start=("a",))
    assert "server busy" in s.offer("b").reject
    assert s.running == ["a"] and not s.waiting
    s.finish("a")
    assert s.offer("c") == Plan(start=("c",))


# ------------------------------------------------------------------ parallel


def test_parallel_runs_up_to_the_limit_then_queues() -> None:
    s = sched("parallel:2")
    assert s.offer("a") == Plan(start=("a",))
    assert s.offer("b") == Plan(start=("b",))
    assert s.offer("c") == Plan()
    assert s.offer("d") == Plan()
    assert s.finish("b") == Plan(start=("c",))
    assert s.running == ["a", "c"]
    assert s.finish("a") == Plan(start=("d",))


def test_unbounded_parallel_starts_everything() -> None:
    s = sched("parallel")
    for g in "abcdef":
        assert s.offer(g) == Plan(start=(g,))
    assert len(s.running) == 6


def test_finish_of_an_unknown_goal_is_harmless() -> None:
    s = sched("queue")
    assert s.finish("ghost") == Plan()


# ------------------------------------------------------------------ states


@pytest.mark.parametrize(
    ("state", "event", "after"),
    [
        (GoalStatus.ACCEPTED, GoalEvent.EXECUTE, GoalStatus.EXECUTING),
        (GoalStatus.ACCEPTED, GoalEvent.CANCEL_GOAL, GoalStatus.CANCELING),
        (GoalStatus.ACCEPTED, GoalEvent.ABORT, GoalStatus.ABORTED),
        (GoalStatus.EXECUTING, GoalEvent.SUCCEED, GoalStatus.SUCCEEDED),
        (GoalStatus.EXECUTING, GoalEvent.ABORT, GoalStatus.ABORTED),
        (GoalStatus.EXECUTING, GoalEvent.CANCEL_GOAL, GoalStatus.CANCELING),
        (GoalStatus.CANCELING, GoalEvent.CANCELED, GoalStatus.CANCELED),
        (GoalStatus.CANCELING, GoalEvent.SUCCEED, GoalStatus.SUCCEEDED),
        (GoalStatus.CANCELING, GoalEvent.ABORT, GoalStatus.ABORTED),
    ],
)
def test_valid_transitions(state: GoalStatus, event: GoalEvent, after: GoalStatus) -> None:
    assert transition(state, event) is after


def test_canceled_without_a_cancel_request_is_refused_with_the_valid_moves() -> None:
    with pytest.raises(GoalStateError) as err:
        transition(GoalStatus.EXECUTING, GoalEvent.CANCELED, "g1")
    assert str(err.value) == ("goal g1 cannot canceled while EXECUTING (cancel was not "
                              "requested); valid now: cancel_goal, succeed, abort")


def test_an_ended_goal_cannot_move() -> None:
    with pytest.raises(GoalStateError, match="valid now: none \\(the goal has ended\\)"):
        transition(GoalStatus.SUCCEEDED, GoalEvent.ABORT)


def test_status_groups() -> None:
    assert [s.name for s in GoalStatus if s.active] == ["ACCEPTED", "EXECUTING", "CANCELING"]
    assert [s.name for s in GoalStatus if s.terminal] == [
        "SUCCEEDED", "CANCELED", "ABORTED", "REJECTED", "LOST"]
