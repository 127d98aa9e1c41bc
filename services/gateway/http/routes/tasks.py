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

from ..api import Answer, Api, ApiError, Call, describe_invalid

__all__ = ["add_task_routes", "decode_body"]

Id = Annotated[str, msgspec.Meta(max_length=64)]
T = TypeVar("T")
JsonObject = dict[str, Any]
"""A body checked by its handler (a task or an action: its type says its fields)."""
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


async def get_task(call: Call[None, IdQuery]) -> Answer:
    """One task (``id``) or all tasks (§8.3)."""
    tasks = call.ctx.tasks
    if call.query.id:
        return as_document(await tasks.get(call.query.id))
    return [as_document(t) for t in await tasks.tasks()]


async def post_task(call: Call[JsonObject, None]) -> Answer:
    """Create a task (state ``WAITTING``) from ``name``, ``sub_tasks``, ``loop_flag``, ..."""
    return as_document(await call.ctx.tasks.create(decode_body(call.body, Task)))


async def put_task(call: Call[JsonObject, None]) -> Answer:
    """Update a task: ``id`` plus ``name``, ``loop_flag`` or ``sub_tasks``."""
    return as_document(await call.ctx.tasks.update(decode_body(call.body, TaskUpdate)))


async def delete_task(call: Call[None, RequiredId]) -> Answer:
    """Delete a task by ``id``."""
    await call.ctx.tasks.command("delete", call.query.id)
    return _OK


async def start_task(call: Call[None, RequiredId]) -> Answer:
    """Start a task."""
    return as_document(await call.ctx.tasks.step("start", call.query.id))


async def pause_task(call: Call[None, RequiredId]) -> Answer:
    """Pause a running task."""
    return as_document(await call.ctx.tasks.step("pause", call.query.id))


async def resume_task(call: Call[None, RequiredId]) -> Answer:
    """Resume a paused task."""
    return as_document(await call.ctx.tasks.step("resume", call.query.id))


async def stop_task(call: Call[None, IdQuery]) -> Answer:
    """Stop a task (the current one without id)."""
    return as_document(await call.ctx.tasks.step("stop", call.query.id))


async def loop(call: Call[None, LoopQuery]) -> Answer:
    """Set or clear a task's ``loop_flag``."""
    return as_document(await call.ctx.tasks.loop(call.query.id, call.query.loop_flag))


async def get_action(call: Call[None, IdQuery]) -> Answer:
    """One action (``id``) or all actions (§9.1)."""
    found = await call.ctx.tasks.actions(call.query.id)
    if call.query.id:
        return found[0] if found else None
    return found


async def post_action(call: Call[JsonObject, None]) -> Answer:
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


async def put_action(call: Call[JsonObject, None]) -> Answer:
    """Change an action: ``id`` plus the fields to change."""
    changes = dict(call.body)
    ident = changes.pop("id", "")
    if not isinstance(ident, str):
        raise ApiError(400, "invalid body: field `id` must be a string")
    return await call.ctx.tasks.update_action(ident, changes)


async def delete_action(call: Call[None, RequiredId]) -> Answer:
    """Delete an action by ``id``."""
    await call.ctx.tasks.command("delete_action", call.query.id)
    return _OK


async def update_wait_req(call: Call[None, None]) -> Answer:
    """Release a task waiting in ``wait_req_action``."""
    await call.ctx.tasks.command("update_wait_req")
    return _OK


def add_task_routes(api: Api) -> None:
    """Route the task and action operations to the tasks service (``call.ctx.tasks``)."""
    api.add("GET", "/task", get_task)
    api.add("POST", "/task", post_task)
    api.add("PUT", "/task", put_task)
    api.add("DELETE", "/task", delete_task)
    api.add("GET", "/task/start", start_task)
    api.add("GET", "/task/pause", pause_task)
    api.add("GET", "/task/resume", resume_task)
    api.add("GET", "/task/stop", stop_task)
    api.add("GET", "/task/loop", loop)
    api.add("GET", "/action", get_action)
    api.add("POST", "/action", post_action)
    api.add("PUT", "/action", put_action)
    api.add("DELETE", "/action", delete_action)
    api.add("GET", "/action/update_wait_req", update_wait_req)
