"""The ``tasks/*`` service calls: decode the body, call the manager, answer with a code.

Codes are HTTP's, so the gateway passes them on as they are: 200, 400 (bad body or
field), 404 (unknown id), 409 (not allowed in the task's state, or another task runs),
504 (a pause or stop that did not take effect in time).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

import msgspec
from zenros.msgs.zenros_msgs.tasks import TaskCallRequest, TaskCallResponse

from .documents import DocumentError
from .manager import TaskBusyError, TaskManager, UnknownTaskError
from .states import TaskStateError

__all__ = ["CALLS", "call"]

MAX_BODY: Final = 1 << 20
_enc = msgspec.json.Encoder()


def _body(req: TaskCallRequest) -> dict[str, Any]:
    if not req.body:
        return {}
    if len(req.body) > MAX_BODY:
        raise DocumentError(f"body of {len(req.body)} characters is over {MAX_BODY}")
    try:
        value = msgspec.json.decode(req.body)
    except (msgspec.DecodeError, RecursionError) as exc:
        raise DocumentError(f"body is not valid JSON: {exc}") from exc
    if not isinstance(value, dict):
        raise DocumentError(f"body must be a JSON object, got {type(value).__name__}")
    return value


def _loop(m: TaskManager, req: TaskCallRequest) -> Any:
    flag = _body(req).get("loop_flag")
    if not isinstance(flag, bool):
        raise DocumentError("field 'loop_flag' must be true or false")
    return m.set_loop(req.id, flag)


def _get(m: TaskManager, req: TaskCallRequest) -> Any:
    return m.get(req.id) if req.id else m.tasks()


def _get_action(m: TaskManager, req: TaskCallRequest) -> Any:
    return m.get_action(req.id) if req.id else m.list_actions()


def _deleted(fn: Callable[[TaskManager, str], None]
             ) -> Callable[[TaskManager, TaskCallRequest], Any]:
    def run(m: TaskManager, req: TaskCallRequest) -> Any:
        fn(m, req.id)
        return {"status": "ok"}
    return run


def _release(m: TaskManager, req: TaskCallRequest) -> Any:
    m.release_wait()
    return {"status": "ok"}


CALLS: Final[dict[str, Callable[[TaskManager, TaskCallRequest], Any]]] = {
    "create": lambda m, r: m.create(_body(r)),
    "get": _get,
    "update": lambda m, r: m.update(r.id or str(_body(r).get("id", "")), _body(r)),
    "delete": _deleted(TaskManager.delete),
    "start": lambda m, r: m.start(r.id),
    "pause": lambda m, r: m.pause(r.id),
    "resume": lambda m, r: m.resume(r.id),
    "stop": lambda m, r: m.stop(r.id or None),
    "loop": _loop,
    "create_action": lambda m, r: m.create_action(_body(r)),
    "get_action": _get_action,
    "update_action": lambda m, r: m.update_action(r.id or str(_body(r).get("id", "")),
                                                  _body(r)),
    "delete_action": _deleted(TaskManager.delete_action),
    "update_wait_req": _release,
}


def call(manager: TaskManager, name: str, req: TaskCallRequest) -> TaskCallResponse:
    """Run call ``name``; every refusal becomes a response with its code and reason."""
    try:
        out = CALLS[name](manager, req)
    except DocumentError as exc:
        return TaskCallResponse(success=False, code=400, message=str(exc))
    except UnknownTaskError as exc:
        return TaskCallResponse(success=False, code=404, message=str(exc))
    except (TaskStateError, TaskBusyError) as exc:
        return TaskCallResponse(success=False, code=409, message=str(exc))
    except TimeoutError as exc:
        return TaskCallResponse(success=False, code=504, message=str(exc))
    return TaskCallResponse(success=True, code=200, body=_enc.encode(out).decode())
