"""zenros_msgs for the tasks service: one call type for its services, and the task status.

Tasks and actions are documents of the robot API (specs/robot-api.md §8-§9): a task's
sub_tasks mix actions of many types with type-specific fields, so they travel as JSON
text in ``body`` and the tasks service validates them against each action type's schema.
"""

from __future__ import annotations

import msgspec

from ...message import Message, define_service
from ..builtin_interfaces import Time

__all__ = ["TaskCall", "TaskCallRequest", "TaskCallResponse", "TaskStatus"]


class TaskCallRequest(Message):
    """A call to one of the ``tasks/*`` services: the target id and a JSON object body."""

    __msgtype__ = "zenros_msgs/TaskCallRequest"
    id: str = ""
    body: str = ""


class TaskCallResponse(Message):
    """The answer: ``code`` is an HTTP status (200 ok, 400 bad request, 404 unknown id,
    409 refused in this state, 503 a service the task needs is unavailable); ``body`` is
    the task, action or list as JSON text, ``message`` the reason of a refusal."""

    __msgtype__ = "zenros_msgs/TaskCallResponse"
    success: bool = False
    code: int = 200
    message: str = ""
    body: str = ""


TaskCall = define_service("zenros_msgs/TaskCall", TaskCallRequest, TaskCallResponse)


class TaskStatus(Message):
    """One task's state after a change; ``tasks/status`` (latched) carries one per change.

    ``task`` is the whole task document (JSON text), as ``GET /task?id=`` returns it.
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
    task: str = ""
