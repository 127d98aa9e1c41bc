"""`TaskManager`: create, change and run tasks; every change stored, then told.

Plain Python with no Zenoh: the node wires its methods to services and its `on_change`
to the ``tasks/status`` topic. One task runs at a time, as on the robot the API comes
from. Errors: `DocumentError` (400), `UnknownTaskError` (404), `TaskStateError` and
`TaskBusyError` (409).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any, Final

import msgspec
from msgspec import UNSET
from zenros.msgs.zenros_msgs.task_actions import Action, ActionBase
from zenros.msgs.zenros_msgs.task_docs import Task, TaskUpdate
from zenros.smach import Container, Execution, State

from .documents import (
    DocumentError,
    Item,
    TaskDoc,
    changes_of,
    find_item,
    is_task,
    kind_of,
    leaves,
    new_action,
    new_task,
    progress_of,
    reset,
    update_action,
    update_task,
    walk,
)
from .machine import build_machine
from .robot import Outcome, Robot
from .states import (
    CANCELLED,
    COMPLETE,
    ERROR,
    FAILED,
    PAUSED,
    TERMINAL,
    WAITTING,
    WORKING,
    TaskStateError,
    check_request,
)
from .store import TaskStore

__all__ = ["TaskBusyError", "TaskManager", "UnknownTaskError"]

_FINAL: Final = {"complete": COMPLETE, "fail": FAILED, "error": ERROR}
STOP_TIMEOUT: Final = 10.0
log = logging.getLogger(__name__)


class UnknownTaskError(KeyError):
    """No task or action with that id (HTTP 404)."""

    def __str__(self) -> str:
        return str(self.args[0])


class TaskBusyError(RuntimeError):
    """Another task is running (HTTP 409)."""


class _Run:
    """One execution of a task's machine, and why it is being stopped (pause/stop)."""

    def __init__(self, doc: Task) -> None:
        self.doc = doc
        self.machine: State | None = None
        self.intent = ""
        self.execution: Execution | None = None
        self.done = threading.Event()
        self.skip: set[str] = set()
        self.detach: Callable[[], None] = lambda: None


class TaskManager:
    """All tasks, their storage and the one running task.

    Args:
        store: Where documents are kept.
        robot: What actions drive.
        on_change: Called with (task, event) after every stored change.
        introspect: Called with (task id, root container) when a run starts; returns a
            function that stops the introspection (the node publishes it for `zenros smach`).
        resume_on_start: Restart a task that was WORKING when the service stopped, instead
            of leaving it PAUSED.
    """

    def __init__(self, store: TaskStore, robot: Robot,
                 on_change: Callable[[Task, str], None] = lambda d, e: None,
                 introspect: Callable[[str, Container], Callable[[], None]] | None = None,
                 resume_on_start: bool = False) -> None:
        self.store = store
        self.robot = robot
        self.on_change = on_change
        self.introspect = introspect
        self.wait_release = threading.Event()
        self._lock = threading.RLock()
        self._tasks: dict[str, Task] = {}
        self._owner: dict[str, str] = {}  # item id -> task id
        self._run: _Run | None = None
        self._at_end: dict[str, list[Callable[[], None]]] = {}  # task id -> cleanups
        self.recovered: list[str] = []
        for doc in store.load():
            self._index(doc)
            if doc.state == WORKING:
                self._settle(doc, PAUSED)
                doc.state = PAUSED
                store.put(doc)
                self.recovered.append(doc.id)
        if resume_on_start:
            for task_id in self.recovered[-1:]:
                self.resume(task_id)

    # ------------------------------------------------------------------ reading

    def tasks(self) -> list[Task]:
        with self._lock:
            return list(self._tasks.values())

    def get(self, task_id: str) -> Task:
        with self._lock:
            return self._task(task_id)

    def get_action(self, action_id: str) -> Action:
        with self._lock:
            task = self._tasks.get(self._owner.get(action_id, ""))
            item = find_item(task, action_id) if task else None
            if item is None or is_task(item):
                raise UnknownTaskError(f"no action with id {action_id!r}")
            return item  # type: ignore[return-value]

    def list_actions(self) -> list[Action]:
        with self._lock:
            return [a for t in self._tasks.values() for a in leaves(t)]

    @property
    def running(self) -> str:
        """The id of the running task, or ''."""
        run = self._run
        return run.doc.id if run is not None else ""

    # ------------------------------------------------------------------ changing

    def create(self, body: Task | Any) -> Task:
        """A new task from ``body``: a `Task`, or the robot API's plain data."""
        doc = new_task(body)
        with self._lock:
            self._index(doc)
            self._commit(doc, "created")
        return doc

    def update(self, task_id: str, body: TaskUpdate | Any) -> Task:
        """Task ``task_id`` with the fields ``body`` (a `TaskUpdate` or plain data) sets."""
        if isinstance(body, TaskUpdate):
            body = changes_of(body)
        if not isinstance(body, dict):
            raise DocumentError("task: expected an object")
        with self._lock:
            doc = self._task(task_id)
            if doc.state in (WORKING, PAUSED) and set(body) - {"id", "name", "loop_flag"}:
                raise TaskStateError(task_id, "change the sub_tasks of", doc.state)
            fresh = update_task(doc, body)
            fresh.state = doc.state
            if doc.state in (WORKING, PAUSED):
                fresh = msgspec.structs.replace(doc, name=fresh.name, loop_flag=fresh.loop_flag)
            self._unindex(doc)
            self._index(fresh)
            if self._run is not None and self._run.doc is doc:
                self._run.doc = fresh
            self._commit(fresh, "updated")
            return fresh

    def delete(self, task_id: str) -> None:
        with self._lock:
            doc = self._task(task_id)
            if doc.state == WORKING:
                raise TaskStateError(task_id, "delete", WORKING)
            self._unindex(doc)
            self.store.delete(task_id)
        self._end(task_id)
        self.on_change(msgspec.structs.replace(
            doc, state=CANCELLED if doc.state not in TERMINAL else doc.state), "deleted")

    def set_loop(self, task_id: str, flag: bool) -> Task:
        return self.update(task_id, {"loop_flag": bool(flag)})

    def create_action(self, body: Action | Any, task_id: str | None = None) -> Task:
        """Add an action (an `Action`, or plain data that may name ``task_id``) to task
        ``task_id``, or to a new task "auto task"."""
        if isinstance(body, dict):
            task_id = body.get("task_id", task_id)
            action_body: Any = {k: v for k, v in body.items() if k != "task_id"}
        elif isinstance(body, ActionBase):
            action_body = body
        else:
            raise DocumentError("action: expected an object")
        if task_id is None:
            return self.create({"name": "auto task", "sub_tasks": [action_body]})
        if not isinstance(task_id, str):
            raise DocumentError("action: field 'task_id' must be str")
        with self._lock:
            doc = self._task(task_id)
            if doc.state in (WORKING, PAUSED):
                raise TaskStateError(task_id, "add an action to", doc.state)
            action = new_action(action_body)
            doc.sub_tasks.append(action)
            self._owner[action.id] = task_id
            self._commit(doc, "updated")
            return doc

    def update_action(self, action_id: str, body: Any) -> Action:
        if not isinstance(body, dict):
            raise DocumentError("action: expected an object")
        with self._lock:
            item = self.get_action(action_id)
            doc = self._tasks[self._owner[action_id]]
            if doc.state in (WORKING, PAUSED):
                raise TaskStateError(doc.id, "change an action of", doc.state)
            fresh = update_action(item, body)
            _replace(doc, item, fresh)
            self._commit(doc, "updated")
            return fresh

    def delete_action(self, action_id: str) -> None:
        with self._lock:
            self.get_action(action_id)
            doc = self._tasks[self._owner[action_id]]
            if doc.state in (WORKING, PAUSED):
                raise TaskStateError(doc.id, "delete an action of", doc.state)
            _remove(doc, action_id)
            del self._owner[action_id]
            self._commit(doc, "updated")

    def release_wait(self) -> None:
        """``update_wait_req``: let a task waiting in ``wait_req_action`` go on."""
        self.wait_release.set()

    # ------------------------------------------------------------------ running

    def start(self, task_id: str) -> Task:
        with self._lock:
            doc = self._task(task_id)
            check_request(task_id, "start", doc.state)
            self._refuse_if_busy(task_id)
            reset(doc)
            doc.loop_count = 0
            doc.result = UNSET
            doc.state = WORKING
            self._commit(doc, "started")
            self._launch(doc)
            return doc

    def resume(self, task_id: str) -> Task:
        with self._lock:
            doc = self._task(task_id)
            check_request(task_id, "resume", doc.state)
            self._refuse_if_busy(task_id)
            for item in walk(doc):
                if item.state == PAUSED:
                    item.state = WAITTING
            doc.state = WORKING
            self._commit(doc, "resumed")
            self._launch(doc, skip_complete=True)
            return doc

    def pause(self, task_id: str, timeout: float = STOP_TIMEOUT) -> Task:
        return self._interrupt(task_id, "pause", timeout)

    def stop(self, task_id: str | None = None, timeout: float = STOP_TIMEOUT) -> Task:
        """Stop ``task_id`` (None: the running task)."""
        if task_id is None or task_id == "":
            task_id = self.running
            if not task_id:
                raise TaskStateError("(none)", "stop", "idle: no task is running")
        return self._interrupt(task_id, "stop", timeout)

    def _interrupt(self, task_id: str, request: str, timeout: float) -> Task:
        with self._lock:
            doc = self._task(task_id)
            check_request(task_id, request, doc.state)
            run = self._run if self._run is not None and self._run.doc is doc else None
            if run is None:  # WAITTING or PAUSED: nothing runs, settle at once
                self._settle(doc, CANCELLED)
                doc.state = CANCELLED
                self._commit(doc, "stopped")
            else:
                run.intent = request
                assert run.execution is not None
                run.execution.request_preempt()
        if run is None:
            self._end(task_id)
            return doc
        if not run.done.wait(timeout):
            raise TimeoutError(f"task {task_id} did not {request} within {timeout:g} s")
        with self._lock:
            return self._tasks.get(task_id, doc)

    def _refuse_if_busy(self, task_id: str) -> None:
        if self._run is not None and self._run.doc.id != task_id:
            raise TaskBusyError(f"task {self._run.doc.id} ({self._run.doc.name!r}) is"
                                " running; pause or stop it before starting another")

    def _launch(self, doc: Task, skip_complete: bool = False) -> None:
        run = _Run(doc)
        run.machine = machine = build_machine(doc, _Hooks(self, run))
        if skip_complete:
            run.skip = {i.id for i in walk(doc) if i.state == COMPLETE}
        self._run = run
        assert isinstance(machine, Container)
        if self.introspect is not None:
            run.detach = self.introspect(doc.id, machine)
        run.execution = machine.execute_in_thread()
        run.execution.add_done_callback(lambda ex: self._on_done(run, ex))

    def _on_done(self, run: _Run, execution: Execution) -> None:
        try:
            outcome = execution.result(0)
            reason = ""
        except Exception as exc:  # noqa: BLE001 (a machine that raised ends its task in ERROR)
            outcome, reason = "error", str(exc)
        relaunch = False
        with self._lock:
            doc = run.doc
            if self._tasks.get(doc.id) is not doc:
                doc = self._tasks.get(doc.id, doc)
            if outcome == "preempted" or run.intent:
                state = PAUSED if run.intent == "pause" else CANCELLED
                if outcome != "preempted":
                    state = _FINAL.get(outcome, ERROR)
                if state in (PAUSED, CANCELLED):
                    self._settle(doc, state)
                event = {PAUSED: "paused", CANCELLED: "stopped"}.get(state, "finished")
            elif outcome == "complete" and doc.loop_flag:
                doc.loop_count += 1
                reset(doc)
                state, event, relaunch = WORKING, "looped", True
            else:
                state = _FINAL.get(outcome, ERROR)
                event = "finished"
            if state == ERROR:
                doc.result = reason or _first_error(doc)
            doc.state = state
            doc.progress = progress_of(doc) if state != COMPLETE else 1.0
            if state in TERMINAL:
                doc.current_task = None
            run.detach()
            self._run = None
            self._commit(doc, event)
            if relaunch:
                self._launch(doc)
        if state in TERMINAL:
            self._end(doc.id)
        run.done.set()

    # ------------------------------------------------------------------ hooks

    def _begin(self, run: _Run, item: Item, parent: TaskDoc) -> bool:
        with self._lock:
            if item.id in run.skip and item.state == COMPLETE:
                return False
            item.state = WORKING
            if not is_task(item):
                item.result = ""
            parent.current_task = item
            if not is_task(item):
                run.doc.current_task = item
            self._commit(run.doc, "progress")
            return True

    def _finish(self, run: _Run, item: Item, outcome: Outcome) -> None:
        with self._lock:
            if outcome.name == "preempted":
                item.state = PAUSED if run.intent == "pause" else CANCELLED
            else:
                item.state = _FINAL[outcome.name]
                if not is_task(item):
                    item.result = outcome.reason
            if item.state == COMPLETE:
                item.progress = 1.0
            elif is_task(item):
                item.progress = progress_of(item)
            run.doc.progress = progress_of(run.doc)
            self._commit(run.doc, "progress")

    def _changed(self, run: _Run) -> None:
        with self._lock:
            run.doc.progress = progress_of(run.doc)
            self._commit(run.doc, "progress")

    # ------------------------------------------------------------------ internals

    def _task(self, task_id: str) -> Task:
        if not isinstance(task_id, str) or not task_id:
            raise DocumentError("missing field 'id' (the task's id)")
        doc = self._tasks.get(task_id)
        if doc is None:
            raise UnknownTaskError(f"no task with id {task_id!r}")
        return doc

    def _index(self, doc: Task) -> None:
        self._tasks[doc.id] = doc
        for item in walk(doc):
            self._owner[item.id] = doc.id

    def _unindex(self, doc: Task) -> None:
        self._tasks.pop(doc.id, None)
        for item in walk(doc):
            self._owner.pop(item.id, None)

    def _end(self, task_id: str) -> None:
        """Task ``task_id`` ended: run what its actions left to undo (`Context.at_end`), last
        first, outside the lock."""
        with self._lock:
            cleanups = self._at_end.pop(task_id, [])
        for cleanup in reversed(cleanups):
            try:
                cleanup()
            except Exception:  # one cleanup's failure must not skip the others
                log.exception("task %s: a cleanup at its end failed", task_id)

    def _commit(self, doc: Task, event: str) -> None:
        self.store.put(doc)
        self.on_change(doc, event)

    @staticmethod
    def _settle(doc: Task, state: str) -> None:
        for item in walk(doc):
            if item.state in (WORKING, PAUSED):
                item.state = state

    def close(self, timeout: float = 5.0) -> None:
        """Pause the running task (it stays PAUSED in the store) and stop."""
        run = self._run
        if run is not None:
            try:
                self.pause(run.doc.id, timeout)
            except (TaskStateError, TimeoutError):
                pass
        for task_id in list(self._at_end):  # what tasks started does not outlive the service
            self._end(task_id)


class _Hooks:
    def __init__(self, manager: TaskManager, run: _Run) -> None:
        self.manager, self.run = manager, run
        self.robot = manager.robot
        self.wait_release = manager.wait_release

    def begin(self, item: Item, parent: TaskDoc) -> bool:
        return self.manager._begin(self.run, item, parent)

    def finish(self, item: Item, outcome: Outcome) -> None:
        self.manager._finish(self.run, item, outcome)

    def changed(self) -> None:
        self.manager._changed(self.run)

    def at_end(self, cleanup: Callable[[], None]) -> None:
        with self.manager._lock:
            self.manager._at_end.setdefault(self.run.doc.id, []).append(cleanup)


def _first_error(doc: Task) -> str:
    for item in walk(doc):
        if item.state == ERROR and not is_task(item) and item.result:
            return f"{kind_of(item)} {item.id}: {item.result}"
    return "failed"


def _remove(doc: TaskDoc, item_id: str) -> bool:
    for i, item in enumerate(doc.sub_tasks):
        if item.id == item_id:
            del doc.sub_tasks[i]
            return True
        if is_task(item) and _remove(item, item_id):
            return True
    return False


def _replace(doc: TaskDoc, old: Item, new: Item) -> bool:
    """Put ``new`` where ``old`` is below ``doc``."""
    for i, item in enumerate(doc.sub_tasks):
        if item is old:
            doc.sub_tasks[i] = new
            return True
        if is_task(item) and _replace(item, old, new):
            return True
    return False
