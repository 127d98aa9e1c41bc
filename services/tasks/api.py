"""The ``tasks/*`` service calls: typed request in, manager call, typed response out.

Every refusal is a response with its `ResultCode`: INVALID (a bad document or field),
NOT_FOUND (unknown id), CONFLICT (not allowed in the task's state, or another task runs),
TIMEOUT (a pause or stop that did not take effect in time). Requests and answers carry
the manager's `Task` / `Action` Structs, copied as they are at the answer.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

import msgspec
from zenros.message import Message, ServiceType
from zenros.msgs.zenros_msgs import tasks as tm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.task_docs import Task

from .documents import DocumentError, snapshot, snapshot_action
from .manager import TaskBusyError, TaskManager, UnknownTaskError
from .states import TaskStateError

__all__ = ["CALLS", "Call", "call"]


def _task(doc: Task | None) -> tm.TaskResponse:
    return tm.TaskResponse(task=None if doc is None else snapshot(doc))


def _get(m: TaskManager, req: tm.GetTasksRequest) -> tm.GetTasksResponse:
    docs = [m.get(req.id)] if req.id else m.tasks()
    return tm.GetTasksResponse(tasks=[snapshot(d) for d in docs])


def _update(m: TaskManager, req: tm.UpdateTaskRequest) -> tm.TaskResponse:
    return _task(m.update(req.update.id, req.update))


def _create_action(m: TaskManager, req: tm.CreateActionRequest) -> tm.TaskResponse:
    if req.action is None:
        raise DocumentError("action: missing field 'action'")
    return _task(m.create_action(req.action, req.task_id))


def _get_action(m: TaskManager, req: tm.GetActionsRequest) -> tm.GetActionsResponse:
    items = [m.get_action(req.id)] if req.id else m.list_actions()
    return tm.GetActionsResponse(actions=[snapshot_action(a) for a in items])


def _update_action(m: TaskManager, req: tm.UpdateActionRequest) -> tm.UpdateActionResponse:
    return tm.UpdateActionResponse(
        action=snapshot_action(m.update_action(req.id, req.changes)))


def _command(fn: Callable[[TaskManager, str], Task | None]
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
    "create": lambda m, r: _task(m.create(r.task)),
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
