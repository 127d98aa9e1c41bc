"""The ``tasks/*`` service calls: typed request in, manager call, typed response out.

Every refusal is a response with its `ResultCode`: INVALID (a bad document or field),
NOT_FOUND (unknown id), CONFLICT (not allowed in the task's state, or another task runs),
TIMEOUT (a pause or stop that did not take effect in time). The manager keeps documents
as plain data; they become `Task` / `Action` Structs here, on the way out.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

import msgspec
from zenros.message import Message, ServiceType
from zenros.msgs.zenros_msgs import tasks as tm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.task_actions import Action
from zenros.msgs.zenros_msgs.task_docs import Task, tag_nested_tasks

from .documents import DocumentError
from .manager import TaskBusyError, TaskManager, UnknownTaskError
from .states import TaskStateError

__all__ = ["CALLS", "Call", "call", "task_struct"]


def task_struct(doc: dict[str, Any]) -> Task:
    """A manager's task document as a `Task`."""
    return msgspec.convert(tag_nested_tasks(doc), Task)


def _task(doc: dict[str, Any] | None) -> tm.TaskResponse:
    return tm.TaskResponse(task=None if doc is None else task_struct(doc))


def _body(value: msgspec.Struct) -> dict[str, Any]:
    out: dict[str, Any] = msgspec.to_builtins(value)
    return out


def _get(m: TaskManager, req: tm.GetTasksRequest) -> tm.GetTasksResponse:
    docs = [m.get(req.id)] if req.id else m.tasks()
    return tm.GetTasksResponse(tasks=[task_struct(d) for d in docs])


def _update(m: TaskManager, req: tm.UpdateTaskRequest) -> tm.TaskResponse:
    return _task(m.update(req.update.id, _body(req.update)))


def _create_action(m: TaskManager, req: tm.CreateActionRequest) -> tm.TaskResponse:
    if req.action is None:
        raise DocumentError("action: missing field 'action'")
    body = _body(req.action)
    if req.task_id is not None:
        body["task_id"] = req.task_id
    return _task(m.create_action(body))


def _get_action(m: TaskManager, req: tm.GetActionsRequest) -> tm.GetActionsResponse:
    docs = [m.get_action(req.id)] if req.id else m.list_actions()
    return tm.GetActionsResponse(actions=[msgspec.convert(d, Action) for d in docs])


def _update_action(m: TaskManager, req: tm.UpdateActionRequest) -> tm.UpdateActionResponse:
    doc = m.update_action(req.id, req.changes)
    return tm.UpdateActionResponse(action=msgspec.convert(doc, Action))


def _command(fn: Callable[[TaskManager, str], dict[str, Any] | None]
             ) -> Callable[[TaskManager, tm.TaskCommandRequest], tm.TaskResponse]:
    def run(m: TaskManager, req: tm.TaskCommandRequest) -> tm.TaskResponse:
        return _task(fn(m, req.id))
    return run


def _release(m: TaskManager, ident: str) -> None:
    m.release_wait()


class Call(msgspec.Struct, frozen=True):
    """One ``tasks/<name>`` service: its type and what it does."""

    srv: ServiceType
    run: Callable[[TaskManager, Any], Message]


_RUN: Final[dict[str, Callable[[TaskManager, Any], Message]]] = {
    "create": lambda m, r: _task(m.create(_body(r.task))),
    "get": _get,
    "update": _update,
    "delete": _command(TaskManager.delete),
    "start": _command(TaskManager.start),
    "pause": _command(TaskManager.pause),
    "resume": _command(TaskManager.resume),
    "stop": _command(lambda m, i: m.stop(i or None)),
    "loop": lambda m, r: _task(m.set_loop(r.id, r.loop_flag)),
    "create_action": _create_action,
    "get_action": _get_action,
    "update_action": _update_action,
    "delete_action": _command(TaskManager.delete_action),
    "update_wait_req": _command(_release),
}
CALLS: Final[dict[str, Call]] = {
    name: Call(srv, _RUN[name]) for name, srv in tm.TASK_SERVICES.items()}

_REFUSALS: Final[tuple[tuple[type[Exception] | tuple[type[Exception], ...], ResultCode], ...]] = (
    (DocumentError, ResultCode.INVALID),
    (UnknownTaskError, ResultCode.NOT_FOUND),
    ((TaskStateError, TaskBusyError), ResultCode.CONFLICT),
    (TimeoutError, ResultCode.TIMEOUT),
)


def call(manager: TaskManager, name: str, req: Message) -> Message:
    """Run call ``name``; every refusal becomes a response with its code and reason."""
    entry = CALLS[name]
    try:
        return entry.run(manager, req)
    except (DocumentError, UnknownTaskError, TaskStateError, TaskBusyError,
            TimeoutError) as exc:
        code = next(c for kinds, c in _REFUSALS if isinstance(exc, kinds))
        refusal: Message = entry.srv.Response(code=code, message=str(exc))
        return refusal
