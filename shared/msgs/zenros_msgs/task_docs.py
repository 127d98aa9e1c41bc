"""Task documents (docs/robot-api.md §8.2): `Task`, a nested `SubTask`, and `TaskUpdate`.

A task's ``sub_tasks`` hold actions (`Action`, tagged by ``type``) and nested tasks. A
nested task is a `SubTask`, tagged ``"type": "task"`` on the wire between services; the
REST API writes nested tasks without ``type`` and reads an item with ``sub_tasks`` as a
task (`tag_nested_tasks` adds the tag before decoding, `untag_nested_tasks` drops it).

Documents are request bodies too, so they refuse unknown fields (a misspelt field is a
400 naming it, not silently ignored): a field added here is added on both sides at once.
"""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from msgspec import UNSET, Meta, UnsetType

from .task_actions import Action

__all__ = ["SubTask", "Task", "TaskItem", "TaskUpdate", "as_document", "tag_nested_tasks",
           "untag_nested_tasks"]

Count = Annotated[int, Meta(ge=1)]


class _TaskFields(msgspec.Struct, kw_only=True, forbid_unknown_fields=True):
    """The fields of a task, top-level or nested."""

    id: str = ""
    name: str = "task"
    sub_tasks: list[TaskItem] = msgspec.field(default_factory=list)
    loop_flag: bool = False
    loop_count: int = 0
    state: str = "WAITTING"
    progress: float = 0.0
    current_task: TaskItem | None = None
    control_type: str | None = "sequence"     # §8.4; null or "" is "sequence"
    blackboard: dict[str, Any] = msgspec.field(default_factory=dict)
    success_count: Count | UnsetType = UNSET      # "parallel" only
    target_loop_count: Count | UnsetType = UNSET  # "loop" only
    result: str | UnsetType = UNSET               # why a task ended in ERROR


class Task(_TaskFields, kw_only=True):
    """A task document, as ``POST /task`` takes it and every task call answers it.

    A request may carry ``type`` (the robot API allows ``"task"``); it is not kept.
    """

    type: str | UnsetType = UNSET


class SubTask(_TaskFields, kw_only=True, tag_field="type", tag="task"):
    """A task inside another task's ``sub_tasks``."""


TaskItem = Action | SubTask
"""One item of ``sub_tasks``: an action or a nested task."""


class TaskUpdate(msgspec.Struct, kw_only=True, forbid_unknown_fields=True):
    """``PUT /task``: the task ``id`` and the fields to change (the others stay)."""

    id: str = ""
    name: str | UnsetType = UNSET
    loop_flag: bool | UnsetType = UNSET
    sub_tasks: list[TaskItem] | UnsetType = UNSET
    control_type: str | None | UnsetType = UNSET
    blackboard: dict[str, Any] | UnsetType = UNSET
    success_count: Count | UnsetType = UNSET
    target_loop_count: Count | UnsetType = UNSET


def _is_task(item: dict[str, Any]) -> bool:
    return "sub_tasks" in item or item.get("type") == "task"


def tag_nested_tasks(doc: Any) -> Any:
    """``doc`` (plain data) with every nested task marked ``"type": "task"``, so it
    decodes as a `Task`; anything else is returned as it is, for the decoder to refuse."""
    if not isinstance(doc, dict):
        return doc
    out = dict(doc)
    subs = out.get("sub_tasks")
    if isinstance(subs, list):
        out["sub_tasks"] = [_tag_item(s) for s in subs]
    if isinstance(out.get("current_task"), dict):
        out["current_task"] = _tag_item(out["current_task"])
    return out


def _tag_item(item: Any) -> Any:
    if not isinstance(item, dict) or not _is_task(item):
        return item
    return {**tag_nested_tasks(item), "type": "task"}


def untag_nested_tasks(doc: dict[str, Any]) -> dict[str, Any]:
    """The REST shape of a task document (plain data): nested tasks without ``type``."""
    subs = doc.get("sub_tasks")
    if isinstance(subs, list):
        doc["sub_tasks"] = [_untag_item(s) for s in subs]
    if isinstance(doc.get("current_task"), dict):
        doc["current_task"] = _untag_item(doc["current_task"])
    return doc


def _untag_item(item: Any) -> Any:
    if isinstance(item, dict) and item.get("type") == "task":
        item.pop("type")
        untag_nested_tasks(item)
    return item


def as_document(task: Task) -> dict[str, Any]:
    """``task`` as the robot API's JSON document (plain data, nested tasks untagged)."""
    return untag_nested_tasks(msgspec.to_builtins(task))
