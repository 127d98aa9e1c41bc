"""Compile a task document into a zenros.smach state machine: actions are its states.

Every state has the outcomes ``complete``, ``fail``, ``error`` and ``preempted``; a
task's ``control_type`` (docs/robot-api.md §8.4) decides how its children's outcomes are wired. A
machine built for a resumed task starts each sequence at its first unfinished child.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, Final, Protocol

from msgspec import UnsetType
from zenros.msgs.zenros_msgs.task_actions import Action
from zenros.msgs.zenros_msgs.task_docs import SubTask
from zenros.smach import Concurrence, State, StateMachine, UserDataAccess

from .actiontypes import action_of
from .behaviors import BEHAVIORS, Context
from .documents import Item, TaskDoc, action_params, kind_of, substitute
from .robot import Outcome, Robot
from .states import COMPLETE

__all__ = ["OUTCOMES", "RunHooks", "build_machine"]

OUTCOMES: Final = ("complete", "fail", "error", "preempted")


class RunHooks(Protocol):
    """The run an item belongs to: the manager records each item's start and end."""

    robot: Robot
    wait_release: threading.Event

    def begin(self, item: Item, parent: TaskDoc) -> bool:
        """Mark ``item`` started; False when it already completed (a resumed run skips it)."""
        ...

    def finish(self, item: Item, outcome: Outcome) -> None: ...

    def changed(self) -> None: ...

    def at_end(self, cleanup: Callable[[], None]) -> None:
        """Call ``cleanup`` once the run's task ends (not at a pause)."""
        ...


class ActionState(State):
    """One action of a task: runs its behaviour and reports the outcome."""

    def __init__(self, item: Action, parent: TaskDoc, board: dict[str, Any],
                 hooks: RunHooks) -> None:
        super().__init__(outcomes=OUTCOMES)
        self.item, self.owner, self.board, self.hooks = item, parent, board, hooks

    def execute(self, userdata: UserDataAccess) -> str:
        if not self.hooks.begin(self.item, self.owner):
            return "complete"
        kind = kind_of(self.item)
        params = substitute(action_params(self.item), self.board)
        ctx = Context(self.hooks.robot, self.item, self.preempt_requested, self.hooks.changed,
                      self.hooks.wait_release, self.hooks.at_end)
        try:
            outcome = BEHAVIORS[kind](ctx, action_of(kind, params))
        except Exception as exc:  # noqa: BLE001 (a behaviour's bug ends the action only)
            outcome = Outcome("error", f"{kind} failed: {type(exc).__name__}: {exc}")
        if outcome.name == "preempted" or (outcome.name != "complete"
                                           and self.preempt_requested()):
            self.service_preempt()
            outcome = Outcome("preempted")
        self.hooks.finish(self.item, outcome)
        return outcome.name


class _TaskContainer(Protocol):
    item: TaskDoc
    parent_item: TaskDoc | None
    hooks: RunHooks


def _as_item(box: _TaskContainer, run: Callable[[], str]) -> str:
    """Run a nested task's container, recording its start and end on its item (the root
    task's state is the manager's to set)."""
    item = box.item
    if box.parent_item is None or not isinstance(item, SubTask):
        return run()
    if not box.hooks.begin(item, box.parent_item):
        return "complete"
    try:
        outcome = run()
    except Exception as exc:
        box.hooks.finish(item, Outcome("error", str(exc)))
        raise
    box.hooks.finish(item, Outcome(outcome))  # type: ignore[arg-type]
    return outcome


class TaskMachine(StateMachine):
    """A nested task: a state machine that records its own start and end on its item."""

    def __init__(self, item: TaskDoc, parent: TaskDoc | None, hooks: RunHooks) -> None:
        super().__init__(outcomes=OUTCOMES)
        self.item, self.parent_item, self.hooks = item, parent, hooks

    def execute(self, userdata: UserDataAccess | None = None) -> str:
        return _as_item(self, lambda: super(TaskMachine, self).execute(userdata))


def _label(i: int, item: Item) -> str:
    return f"{i:02d}_{kind_of(item).upper()}"


def build_machine(doc: TaskDoc, hooks: RunHooks, parent: TaskDoc | None = None,
                  board: dict[str, Any] | None = None) -> State:
    """The state (machine) that runs ``doc``; ``parent`` is None for the root task."""
    scope = {**(board or {}), **doc.blackboard}
    children: list[tuple[str, State]] = []
    for i, item in enumerate(doc.sub_tasks):
        state: State
        if isinstance(item, SubTask):
            state = build_machine(item, hooks, doc, scope)
        else:
            state = ActionState(item, doc, scope, hooks)
        children.append((_label(i, item), state))
    control = doc.control_type or "sequence"
    if control == "parallel":
        return _parallel(doc, parent, hooks, children)
    sm = TaskMachine(doc, parent, hooks)
    if not children:
        sm.add("00_EMPTY", _Done(), transitions={"complete": "complete"})
        return sm
    if control == "loop":
        target = doc.target_loop_count
        _wire_loop(sm, children[0], 1 if isinstance(target, UnsetType) else target)
        return sm
    labels = [label for label, _ in children]
    for i, (label, state) in enumerate(children):
        nxt = labels[i + 1] if i + 1 < len(labels) else "complete"
        sm.add(label, state, transitions=_transitions(control, label, labels[0], nxt, i,
                                                      len(labels)))
    sm.set_initial_state([_first_unfinished(doc, control, labels)])
    return sm


def _transitions(control: str, label: str, first: str, nxt: str, i: int,
                 n: int) -> dict[str, str]:
    last_fail = "fail"
    match control:
        case "sequence":
            return {"complete": nxt, "fail": "fail"}
        case "restart_sequence":
            return {"complete": nxt, "fail": first}
        case "retry_sequence":
            return {"complete": nxt, "fail": label}
        case "fallback":
            nxt_fail = nxt if i + 1 < n else last_fail
            return {"complete": "complete", "fail": nxt_fail}
        case "flip":
            return {"complete": "fail", "fail": "complete"}
        case "force_fail":
            return {"complete": "fail", "fail": "fail"}
        case "force_success":
            return {"complete": "complete", "fail": "complete"}
        case "retry_until_success":
            return {"complete": "complete", "fail": label}
    raise ValueError(f"unknown control_type {control!r}")


def _first_unfinished(doc: TaskDoc, control: str, labels: list[str]) -> str:
    if control not in ("sequence", "restart_sequence", "retry_sequence"):
        return labels[0]
    for label, item in zip(labels, doc.sub_tasks, strict=True):
        if item.state != COMPLETE:
            return label
    return labels[-1]


class _Done(State):
    def __init__(self) -> None:
        super().__init__(outcomes=["complete"])

    def execute(self, userdata: UserDataAccess) -> str:
        return "complete"


class _Counter(State):
    """Counts the loop's runs of its child: ``again`` until ``target`` runs are done."""

    def __init__(self, item: TaskDoc, target: int) -> None:
        super().__init__(outcomes=["again", "done"])
        self.item, self.target, self.runs = item, target, -1

    def execute(self, userdata: UserDataAccess) -> str:
        self.runs += 1
        if self.runs >= self.target:
            return "done"
        if self.runs > 0:
            for sub in self.item.sub_tasks:
                sub.state = "WAITTING"
        return "again"


def _wire_loop(sm: TaskMachine, child: tuple[str, State], target: int) -> None:
    label, state = child
    sm.add("00_COUNT", _Counter(sm.item, target),
           transitions={"again": label, "done": "complete"})
    sm.add(label, state, transitions={"complete": "00_COUNT", "fail": "fail"})


def _parallel(doc: TaskDoc, parent: TaskDoc | None, hooks: RunHooks,
              children: list[tuple[str, State]]) -> State:
    need = len(children) if isinstance(doc.success_count, UnsetType) else doc.success_count

    def decide(outcomes: dict[str, str]) -> str:
        values = list(outcomes.values())
        if "error" in values:
            return "error"
        if "preempted" in values:
            return "preempted"
        return "complete" if values.count("complete") >= need else "fail"

    con = _TaskConcurrence(doc, parent, hooks, decide)
    for label, state in children:
        con.add(label, state)
    return con


class _TaskConcurrence(Concurrence):
    """A parallel task: children at once; complete when ``success_count`` complete."""

    def __init__(self, item: TaskDoc, parent: TaskDoc | None, hooks: RunHooks,
                 decide: Any) -> None:
        super().__init__(outcomes=OUTCOMES, default_outcome="fail", outcome_cb=decide)
        self.item, self.parent_item, self.hooks = item, parent, hooks

    def execute(self, userdata: UserDataAccess | None = None) -> str:
        return _as_item(self, lambda: super(_TaskConcurrence, self).execute(userdata))


