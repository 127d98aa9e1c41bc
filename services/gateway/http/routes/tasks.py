"""REST ``/task`` and ``/action`` (docs/robot-api.md §8.3, §9.1), forwarded to the tasks service's
``tasks/*``.

Bodies decode straight into the task documents (`Task`, `TaskUpdate`, `Action`): a bad one
is a 400 naming the field's path (``sub_tasks[0].wait_time``) before the tasks service is
asked. Answers are the documents as the robot API writes them (`as_document`).
"""

from __future__ import annotations

from typing import Annotated, Any, TypeVar

import msgspec
from zenros.msgs.zenros_msgs.task_actions import Action
from zenros.msgs.zenros_msgs.task_docs import Task, TaskUpdate, as_document, tag_nested_tasks

from ..api import Api, ApiError, Call, describe_invalid

__all__ = ["add_task_routes", "decode_body"]

Id = Annotated[str, msgspec.Meta(max_length=64)]
T = TypeVar("T")
_OK = {"status": "ok"}


class IdQuery(msgspec.Struct, forbid_unknown_fields=True):
    id: Id = ""


class RequiredId(msgspec.Struct, forbid_unknown_fields=True):
    id: Id


class LoopQuery(msgspec.Struct, forbid_unknown_fields=True):
    id: Id
    loop_flag: bool


def decode_body(body: Any, kind: type[T] | Any) -> T:
    """A REST body (plain data) as ``kind`` (nested tasks read by their ``sub_tasks``); a
    400 naming the field when it does not fit."""
    try:
        value: T = msgspec.convert(tag_nested_tasks(body), kind, strict=True)
    except msgspec.ValidationError as exc:
        raise ApiError(400, describe_invalid(exc, "body")) from exc
    return value


async def get_task(call: Call) -> Any:
    """One task (``id``) or all tasks (§8.3)."""
    tasks = call.ctx.tasks
    if call.query.id:
        return as_document(await tasks.get(call.query.id))
    return [as_document(t) for t in await tasks.tasks()]


async def post_task(call: Call) -> Any:
    """Create a task (state ``WAITTING``) from ``name``, ``sub_tasks``, ``loop_flag``, ..."""
    return as_document(await call.ctx.tasks.create(decode_body(call.body, Task)))


async def put_task(call: Call) -> Any:
    """Update a task: ``id`` plus ``name``, ``loop_flag`` or ``sub_tasks``."""
    return as_document(await call.ctx.tasks.update(decode_body(call.body, TaskUpdate)))


async def delete_task(call: Call) -> Any:
    """Delete a task by ``id``."""
    await call.ctx.tasks.command("delete", call.query.id)
    return _OK


async def start_task(call: Call) -> Any:
    """Start a task."""
    return as_document(await call.ctx.tasks.step("start", call.query.id))


async def pause_task(call: Call) -> Any:
    """Pause a running task."""
    return as_document(await call.ctx.tasks.step("pause", call.query.id))


async def resume_task(call: Call) -> Any:
    """Resume a paused task."""
    return as_document(await call.ctx.tasks.step("resume", call.query.id))


async def stop_task(call: Call) -> Any:
    """Stop a task (the current one without id)."""
    return as_document(await call.ctx.tasks.step("stop", call.query.id))


async def loop(call: Call) -> Any:
    """Set or clear a task's ``loop_flag``."""
    return as_document(await call.ctx.tasks.loop(call.query.id, call.query.loop_flag))


async def get_action(call: Call) -> Any:
    """One action (``id``) or all actions (§9.1)."""
    found = await call.ctx.tasks.actions(call.query.id)
    if call.query.id:
        return msgspec.to_builtins(found[0]) if found else None
    return msgspec.to_builtins(found)


async def post_action(call: Call) -> Any:
    """Add an action (``type`` + params) to ``task_id``, or to a new ``auto task``."""
    body = dict(call.body)
    if not isinstance(body.get("type"), str):
        raise ApiError(400, "invalid body: field `type` (the action type, §9.2) is "
                            "required and must be a string")
    task_id = body.pop("task_id", None)
    if task_id is not None and not isinstance(task_id, str):
        raise ApiError(400, "invalid body: field `task_id` must be a string")
    action: Action = decode_body(body, Action)
    return as_document(await call.ctx.tasks.create_action(task_id, action))


async def put_action(call: Call) -> Any:
    """Change an action: ``id`` plus the fields to change."""
    changes = dict(call.body)
    ident = changes.pop("id", "")
    if not isinstance(ident, str):
        raise ApiError(400, "invalid body: field `id` must be a string")
    return msgspec.to_builtins(await call.ctx.tasks.update_action(ident, changes))


async def delete_action(call: Call) -> Any:
    """Delete an action by ``id``."""
    await call.ctx.tasks.command("delete_action", call.query.id)
    return _OK


async def update_wait_req(call: Call) -> Any:
    """Release a task waiting in ``wait_req_action``."""
    await call.ctx.tasks.command("update_wait_req")
    return _OK


def add_task_routes(api: Api) -> None:
    """Route the task and action operations to the tasks service (``call.ctx.tasks``)."""
    body_dict: Any = dict[str, Any]
    api.add("GET", "/task", get_task, query=IdQuery)
    api.add("POST", "/task", post_task, body=body_dict)
    api.add("PUT", "/task", put_task, body=body_dict)
    api.add("DELETE", "/task", delete_task, query=RequiredId)
    api.add("GET", "/task/start", start_task, query=RequiredId)
    api.add("GET", "/task/pause", pause_task, query=RequiredId)
    api.add("GET", "/task/resume", resume_task, query=RequiredId)
    api.add("GET", "/task/stop", stop_task, query=IdQuery)
    api.add("GET", "/task/loop", loop, query=LoopQuery)
    api.add("GET", "/action", get_action, query=IdQuery)
    api.add("POST", "/action", post_action, body=body_dict)
    api.add("PUT", "/action", put_action, body=body_dict)
    api.add("DELETE", "/action", delete_action, query=RequiredId)
    api.add("GET", "/action/update_wait_req", update_wait_req)
