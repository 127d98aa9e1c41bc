"""``python -m zenros.services.tasks``: run the task manager."""

from zenros import run

from .node import TasksNode

run(TasksNode)
