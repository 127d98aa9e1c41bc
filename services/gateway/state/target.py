"""`task_target`: the docs/robot-api.md §4 ``targetNumID`` of the goal a task is driving.

The task's own document says which goal it drives (``current_task``, on ``tasks/status``):
a ``nav_action`` to a nav point ``index`` is that nav point, one to ``x``/``y`` a goal
without an id (-2). Reading it from the task, not from the route that started the task,
keeps the number right for every leg of a patrol and for tasks the gateway did not start.
"""

from __future__ import annotations

from zenros.msgs.zenros_msgs.task_actions import NavAction
from zenros.msgs.zenros_msgs.task_docs import Task

__all__ = ["NO_ID", "task_target"]

NO_ID = -2  # §4: a goal without a nav-point id


def task_target(task: Task) -> int | None:
    """The ``targetNumID`` of the nav goal ``task`` is driving now: the nav point's index,
    or `NO_ID`; None when its current action is not a nav goal (or there is none)."""
    item = task.current_task
    while item is not None and not isinstance(item, NavAction):
        item = getattr(item, "current_task", None)  # a nested task: its running item
    if item is None:
        return None
    return item.index if isinstance(item.index, int) else NO_ID
