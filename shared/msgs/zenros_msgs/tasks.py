"""zenros_msgs for the tasks service: one request/response pair per call, and the status.

Tasks and actions are the robot API's documents (docs/robot-api.md §8-§9) as Structs
(`Task`, `Action`). Every response carries a `ResultCode` and, on a refusal, the reason
in ``message``; a caller branches on the code only.

=================  ================  ==========================================
service            type              answers
=================  ================  ==========================================
tasks/create       CreateTask        the created task
tasks/get          GetTasks          ``tasks``: the one with ``id``, or all
tasks/update       UpdateTask        the updated task
tasks/delete       TaskCommand       nothing (``task`` is null)
tasks/start        TaskCommand       the started task
tasks/pause        TaskCommand       the paused task
tasks/resume       TaskCommand       the resumed task
tasks/stop         TaskCommand       the stopped task (no ``id``: the running one)
tasks/loop         SetTaskLoop       the task with its new ``loop_flag``
tasks/create_action CreateAction     the task the action was added to
tasks/get_action   GetActions        ``actions``: the one with ``id``, or all
tasks/update_action UpdateAction     the changed action
tasks/delete_action TaskCommand      nothing
tasks/update_wait_req TaskCommand    nothing (releases a ``wait_req_action``)
=================  ================  ==========================================
"""

from __future__ import annotations

from typing import Any, Final

import msgspec

from ...message import Message, ServiceType, define_service
from ..builtin_interfaces import Time
from .result import ResultCode
from .task_actions import Action
from .task_docs import Task, TaskUpdate, as_document, tag_nested_tasks

__all__ = [
    "TASK_SERVICES",
    "CreateAction",
    "CreateActionRequest",
    "CreateTask",
    "CreateTaskRequest",
    "GetActions",
    "GetActionsRequest",
    "GetActionsResponse",
    "GetTasks",
    "GetTasksRequest",
    "GetTasksResponse",
    "SetTaskLoop",
    "SetTaskLoopRequest",
    "TaskCommand",
    "TaskCommandRequest",
    "TaskResponse",
    "TaskStatus",
    "UpdateAction",
    "UpdateActionRequest",
    "UpdateActionResponse",
    "UpdateTask",
    "UpdateTaskRequest",
    "response_data",
    "task_request",
]


class TaskResponse(Message):
    """A call's answer: ``code`` (OK, or why not) and the task it concerns (or null)."""

    __msgtype__ = "zenros_msgs/TaskResponse"
    code: ResultCode = ResultCode.OK
    message: str = ""
    task: Task | None = None


class CreateTaskRequest(Message):
    __msgtype__ = "zenros_msgs/CreateTaskRequest"
    task: Task = msgspec.field(default_factory=Task)


class GetTasksRequest(Message):
    __msgtype__ = "zenros_msgs/GetTasksRequest"
    id: str = ""  # "": every task


class GetTasksResponse(Message):
    __msgtype__ = "zenros_msgs/GetTasksResponse"
    code: ResultCode = ResultCode.OK
    message: str = ""
    tasks: list[Task] = msgspec.field(default_factory=list)


class UpdateTaskRequest(Message):
    __msgtype__ = "zenros_msgs/UpdateTaskRequest"
    update: TaskUpdate = msgspec.field(default_factory=TaskUpdate)


class TaskCommandRequest(Message):
    """The task (or action) ``id`` a command applies to."""

    __msgtype__ = "zenros_msgs/TaskCommandRequest"
    id: str = ""


class SetTaskLoopRequest(Message):
    __msgtype__ = "zenros_msgs/SetTaskLoopRequest"
    id: str = ""
    loop_flag: bool = False


class CreateActionRequest(Message):
    """Add ``action`` to task ``task_id``, or (null) to a new task named "auto task"."""

    __msgtype__ = "zenros_msgs/CreateActionRequest"
    task_id: str | None = None
    action: Action | None = None


class GetActionsRequest(Message):
    __msgtype__ = "zenros_msgs/GetActionsRequest"
    id: str = ""  # "": every action of every task


class GetActionsResponse(Message):
    __msgtype__ = "zenros_msgs/GetActionsResponse"
    code: ResultCode = ResultCode.OK
    message: str = ""
    actions: list[Action] = msgspec.field(default_factory=list)


class UpdateActionRequest(Message):
    """Change action ``id``: ``changes`` holds the parameters to change (checked against
    the action's type once merged, so their type is only known there)."""

    __msgtype__ = "zenros_msgs/UpdateActionRequest"
    id: str = ""
    changes: dict[str, Any] = msgspec.field(default_factory=dict)


class UpdateActionResponse(Message):
    __msgtype__ = "zenros_msgs/UpdateActionResponse"
    code: ResultCode = ResultCode.OK
    message: str = ""
    action: Action | None = None


CreateTask = define_service("zenros_msgs/CreateTask", CreateTaskRequest, TaskResponse)
GetTasks = define_service("zenros_msgs/GetTasks", GetTasksRequest, GetTasksResponse)
UpdateTask = define_service("zenros_msgs/UpdateTask", UpdateTaskRequest, TaskResponse)
TaskCommand = define_service("zenros_msgs/TaskCommand", TaskCommandRequest, TaskResponse)
SetTaskLoop = define_service("zenros_msgs/SetTaskLoop", SetTaskLoopRequest, TaskResponse)
CreateAction = define_service("zenros_msgs/CreateAction", CreateActionRequest, TaskResponse)
GetActions = define_service("zenros_msgs/GetActions", GetActionsRequest, GetActionsResponse)
UpdateAction = define_service("zenros_msgs/UpdateAction", UpdateActionRequest,
                              UpdateActionResponse)

TASK_SERVICES: Final[dict[str, ServiceType]] = {
    "create": CreateTask,
    "get": GetTasks,
    "update": UpdateTask,
    "delete": TaskCommand,
    "start": TaskCommand,
    "pause": TaskCommand,
    "resume": TaskCommand,
    "stop": TaskCommand,
    "loop": SetTaskLoop,
    "create_action": CreateAction,
    "get_action": GetActions,
    "update_action": UpdateAction,
    "delete_action": TaskCommand,
    "update_wait_req": TaskCommand,
}
"""The ``tasks/<name>`` services and their types (the table above)."""


class TaskStatus(Message):
    """One task's state after a change; ``tasks/status`` (latched) carries one per change.

    ``task`` is the whole task document, as ``GET /task?id=`` returns it.
    """

    __msgtype__ = "zenros_msgs/TaskStatus"
    stamp: Time = msgspec.field(default_factory=Time)
    id: str = ""
    name: str = ""
    state: str = ""
    progress: float = 0.0
    loop_count: int = 0
    current_id: str = ""
    current_type: str = ""
    event: str = ""
    task: Task = msgspec.field(default_factory=Task)


def task_request(name: str, ident: str = "", body: Any = None) -> Message:
    """The request of ``tasks/<name>`` from the robot API's plain data (as a CLI or a test
    has it): ``ident`` is the id, ``body`` the JSON-like document of create, update, loop,
    create_action (``task_id`` beside the action's fields) and update_action.

    Raises:
        msgspec.ValidationError: ``body`` does not fit, naming the field's path.
        KeyError: no such call.
    """
    srv = TASK_SERVICES[name]
    data: dict[str, Any] = dict(body or {})
    if srv is CreateTask:
        return CreateTaskRequest(task=msgspec.convert(tag_nested_tasks(data), Task))
    if srv is UpdateTask:
        return UpdateTaskRequest(update=msgspec.convert(
            tag_nested_tasks({"id": ident, **data}), TaskUpdate))
    if srv is SetTaskLoop:
        return msgspec.convert({"id": ident, **data}, SetTaskLoopRequest)
    if srv is CreateAction:
        task_id = data.pop("task_id", None)
        return msgspec.convert({"task_id": task_id, "action": data}, CreateActionRequest)
    if srv is UpdateAction:
        return UpdateActionRequest(id=ident, changes=data)
    if srv is GetTasks:
        return GetTasksRequest(id=ident)
    if srv is GetActions:
        return GetActionsRequest(id=ident)
    return TaskCommandRequest(id=ident)


def response_data(res: Message, single: bool = False) -> Any:
    """A ``tasks/*`` response's document(s) as the robot API's plain data (None for a
    refusal or a call that answers none); ``single``: the one of a get by id."""
    if isinstance(res, GetTasksResponse):
        docs: list[Any] = [as_document(t) for t in res.tasks]
    elif isinstance(res, GetActionsResponse):
        docs = msgspec.to_builtins(res.actions)
    elif isinstance(res, TaskResponse):
        return None if res.task is None else as_document(res.task)
    elif isinstance(res, UpdateActionResponse):
        return None if res.action is None else msgspec.to_builtins(res.action)
    else:
        return None
    return (docs[0] if docs else None) if single else docs
