"""REST ``/task`` and ``/action`` (§8.3, §9.1), forwarded to the tasks service's ``tasks/*``."""

from __future__ import annotations

from typing import Annotated, Any

import msgspec

from ..api import Api, ApiError, Call

__all__ = ["add_task_routes"]

Id = Annotated[str, msgspec.Meta(max_length=64)]
_ENC = msgspec.json.Encoder()


class IdQuery(msgspec.Struct, forbid_unknown_fields=True):
    id: Id = ""


class RequiredId(msgspec.Struct, forbid_unknown_fields=True):
    id: Id


class LoopQuery(msgspec.Struct, forbid_unknown_fields=True):
    id: Id
    loop_flag: bool


async def forward(call: Call, name: str, ident: str = "", body: Any = None) -> Any:
    """Call ``tasks/<name>`` with ``ident`` and ``body``; its JSON answer as is."""
    reply = await call.ctx.tasks(name, ident, "" if body is None
                                 else _ENC.encode(body).decode())
    if reply.code != 200:
        raise reply.error(name)
    return msgspec.Raw(reply.body.encode())


def raw_body(call: Call) -> Any:
    return call.body if isinstance(call.body, dict) else msgspec.to_builtins(call.body)


async def get_task(call: Call) -> Any:
    """One task (``id``) or all tasks (§8.3)."""
    return await forward(call, "get", call.query.id)


async def post_task(call: Call) -> Any:
    """Create a task (state ``WAITTING``) from ``name``, ``sub_tasks``, ``loop_flag``, ..."""
    return await forward(call, "create", "", raw_body(call))


async def put_task(call: Call) -> Any:
    """Update a task: ``id`` plus ``name``, ``loop_flag`` or ``sub_tasks``."""
    body = raw_body(call)
    return await forward(call, "update", str(body.get("id", "")), body)


async def delete_task(call: Call) -> Any:
    """Delete a task by ``id``."""
    return await forward(call, "delete", call.query.id)


async def start_task(call: Call) -> Any:
    """Start a task."""
    return await forward(call, "start", call.query.id)


async def pause_task(call: Call) -> Any:
    """Pause a running task."""
    return await forward(call, "pause", call.query.id)


async def resume_task(call: Call) -> Any:
    """Resume a paused task."""
    return await forward(call, "resume", call.query.id)


async def stop_task(call: Call) -> Any:
    """Stop a task (the current one without id)."""
    return await forward(call, "stop", call.query.id)


async def loop(call: Call) -> Any:
    """Set or clear a task's ``loop_flag``."""
    return await forward(call, "loop", call.query.id, {"loop_flag": call.query.loop_flag})


async def get_action(call: Call) -> Any:
    """One action (``id``) or all actions (§9.1)."""
    return await forward(call, "get_action", call.query.id)


async def post_action(call: Call) -> Any:
    """Add an action (``type`` + params) to ``task_id``, or to a new ``auto task``."""
    body = raw_body(call)
    if not isinstance(body.get("type"), str):
        raise ApiError(400, "invalid body: field `type` (the action type, §9.2) is "
                            "required and must be a string")
    return await forward(call, "create_action", "", body)


async def put_action(call: Call) -> Any:
    """Change an action: ``id`` plus the fields to change."""
    body = raw_body(call)
    return await forward(call, "update_action", str(body.get("id", "")), body)


async def delete_action(call: Call) -> Any:
    """Delete an action by ``id``."""
    return await forward(call, "delete_action", call.query.id)


async def update_wait_req(call: Call) -> Any:
    """Release a task waiting in ``wait_req_action``."""
    return await forward(call, "update_wait_req")


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
