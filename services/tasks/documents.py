"""Task and action documents (docs/robot-api.md §8.2, §9): creation, walking, progress.

A task is a `Task` Struct (zenros_msgs.task_docs) end to end: created here, run, stored
and served as it is. An item of ``sub_tasks`` is an `Action` (tagged by ``type``) or a
nested task, a `SubTask`. A request body may be that Struct or the robot API's plain
data (a test, the CLI); both are checked here with errors naming the field.
"""

from __future__ import annotations

import uuid
from collections.abc import Iterator, Mapping
from typing import Any, Final, TypeGuard

import msgspec
from msgspec import UNSET
from zenros.msgs.zenros_msgs.task_actions import (
    COMMON_FIELDS,
    Action,
    ActionBase,
    Location,
    check_action,
)
from zenros.msgs.zenros_msgs.task_docs import SubTask, Task, TaskUpdate

from .actiontypes import ActionParamsError, parse_action
from .states import COMPLETE, WAITTING

__all__ = [
    "CONTROL_TYPES", "DocumentError", "Item", "TaskDoc", "action_params", "changes_of",
    "find_item", "is_task", "kind_of", "leaves", "new_action", "new_task", "progress_of",
    "reset", "snapshot", "snapshot_action", "substitute", "update_action", "update_task",
    "walk",
]

TaskDoc = Task | SubTask
"""A task document: the top-level `Task` or a nested `SubTask`."""
Item = Action | SubTask
"""One item of a task's ``sub_tasks``."""

# control type -> (min children, max children or None, its extra integer parameter)
CONTROL_TYPES: Final[dict[str, tuple[int, int | None, str | None]]] = {
    "sequence": (0, None, None),
    "parallel": (1, None, "success_count"),
    "fallback": (1, None, None),
    "flip": (1, 1, None),
    "loop": (1, 1, "target_loop_count"),
    "force_fail": (1, 1, None),
    "force_success": (1, 1, None),
    "restart_sequence": (0, None, None),
    "retry_sequence": (0, None, None),
    "retry_until_success": (1, 1, None),
}
_TASK_FIELDS: Final = frozenset({"id", "name", "sub_tasks", "loop_flag", "loop_count", "state",
                                 "progress", "current_task", "control_type", "blackboard",
                                 "success_count", "target_loop_count", "type"})
_CHANGEABLE: Final = frozenset({"id", "name", "loop_flag", "sub_tasks", "control_type",
                                "blackboard", "success_count", "target_loop_count"})
_COPY: Final = msgspec.msgpack.Encoder()
_TASK_COPY: Final = msgspec.msgpack.Decoder(Task)
_ACTION_COPY: Final = msgspec.msgpack.Decoder(Action)
MAX_ITEMS: Final = 10_000
MAX_DEPTH: Final = 16


class DocumentError(ValueError):
    """A task or action body that is not valid; the text names the field (HTTP 400)."""


def snapshot(doc: Task) -> Task:
    """A deep copy of ``doc`` as it is now, for a reader outside the manager (an answer, a
    status message): the running task goes on changing the original."""
    return _TASK_COPY.decode(_COPY.encode(doc))


def snapshot_action(item: Action) -> Action:
    """A deep copy of action ``item`` as it is now (see `snapshot`)."""
    copy: Action = _ACTION_COPY.decode(_COPY.encode(item))
    return copy


def is_task(item: object) -> TypeGuard[TaskDoc]:
    """Whether ``item`` is a (nested) task rather than an action."""
    return isinstance(item, Task | SubTask)


def _is_task_body(body: Mapping[str, Any]) -> bool:
    return "sub_tasks" in body or body.get("type") == "task"


def kind_of(item: Item | Task) -> str:
    """An item's ``type``: the action type, or "task"."""
    return "task" if is_task(item) else str(item.__struct_config__.tag)


def _fresh(action: Action) -> Action:
    """``action`` as a new document item: a new id, WAITTING, nothing done yet; a
    parameter given as null is not given (UNSET)."""
    for name in action.__struct_fields__:
        if name not in COMMON_FIELDS and getattr(action, name) is None:
            setattr(action, name, UNSET)
    action.id = str(uuid.uuid4())
    action.state, action.result, action.progress = WAITTING, "", 0.0
    nav = kind_of(action) == "nav_action"
    action.current_location = Location() if nav else UNSET
    action.current_distance = -1.0 if nav else UNSET
    return action


def new_action(body: Any, where: str = "action") -> Action:
    """A fresh action document (new id, WAITTING) from a request body: an `Action` or
    plain data."""
    if isinstance(body, ActionBase):
        try:
            check_action(body)
        except ValueError as exc:
            raise DocumentError(f"{where} {exc}") from exc
        return _fresh(msgspec.structs.replace(body))  # type: ignore[arg-type]
    if not isinstance(body, dict):
        raise DocumentError(f"{where}: expected an object, got {type(body).__name__}")
    try:
        return _fresh(parse_action(body, where))
    except ActionParamsError as exc:
        raise DocumentError(str(exc)) from exc


def _given(body: Any, where: str) -> Mapping[str, Any]:
    """The fields of a task body: a task Struct's set fields, or plain data checked."""
    if is_task(body):
        return {f: getattr(body, f) for f in body.__struct_fields__
                if getattr(body, f) is not UNSET}
    if not isinstance(body, dict):
        raise DocumentError(f"{where}: expected an object, got {type(body).__name__}")
    unknown = sorted(set(body) - _TASK_FIELDS)
    if unknown:
        raise DocumentError(f"{where}: unknown field {unknown[0]!r}; task fields: "
                            + ", ".join(sorted(_TASK_FIELDS - {'type'})))
    return body


def new_task(body: Any, where: str = "task") -> Task:
    """A fresh task document (new ids, WAITTING everywhere) from a request body: a `Task`
    or plain data."""
    doc = _new_task(Task, body, where, 0, [0])
    assert isinstance(doc, Task)
    return doc


def _new_task(cls: type[TaskDoc], body: Any, where: str, depth: int,
              counter: list[int]) -> TaskDoc:
    given = _given(body, where)
    if depth > MAX_DEPTH:
        raise DocumentError(f"{where}: tasks nest deeper than {MAX_DEPTH} levels")
    name = given.get("name", "task")
    loop_flag = given.get("loop_flag", False)
    subs = given.get("sub_tasks", [])
    control = given.get("control_type") or "sequence"
    board = given.get("blackboard", {})
    _expect(where, "name", name, str)
    _expect(where, "loop_flag", loop_flag, bool)
    _expect(where, "sub_tasks", subs, list)
    _expect(where, "control_type", control, str)
    _expect(where, "blackboard", board, dict)
    if control not in CONTROL_TYPES:
        raise DocumentError(f"{where}: unknown control_type {control!r}; control types: "
                            + ", ".join(CONTROL_TYPES))
    lo, hi, extra = CONTROL_TYPES[control]
    if len(subs) < lo or (hi is not None and len(subs) > hi):
        want = f"exactly {lo}" if hi == lo else f"at least {lo}"
        raise DocumentError(f"{where}: control_type {control} takes {want} sub_task(s),"
                            f" got {len(subs)}")
    items: list[Item] = []
    for i, sub in enumerate(subs):
        counter[0] += 1
        if counter[0] > MAX_ITEMS:
            raise DocumentError(f"{where}: more than {MAX_ITEMS} sub_tasks in all")
        at = f"{where}.sub_tasks[{i}]"
        if is_task(sub) or (isinstance(sub, dict) and _is_task_body(sub)):
            nested = {k: v for k, v in sub.items() if k != "type"} if isinstance(sub, dict) \
                else sub
            items.append(_new_task(SubTask, nested, at, depth + 1, counter))  # type: ignore[arg-type]
        else:
            items.append(new_action(sub, at))
    doc = cls(id=str(uuid.uuid4()), name=name, sub_tasks=items, loop_flag=loop_flag,
              loop_count=0, state=WAITTING, progress=0.0, current_task=None,
              control_type=control, blackboard=board)
    if extra is not None:
        value = given.get(extra, len(items) if extra == "success_count" else 1)
        if not isinstance(value, int) or isinstance(value, bool) or value < 1:
            raise DocumentError(f"{where}: {extra} must be an integer >= 1, got {value!r}")
        setattr(doc, extra, value)
    return doc


def changes_of(update: TaskUpdate) -> dict[str, Any]:
    """The fields a `TaskUpdate` sets (its ``id`` included), by name."""
    return {f: getattr(update, f) for f in update.__struct_fields__
            if getattr(update, f) is not UNSET}


def update_task(doc: Task, body: Mapping[str, Any]) -> Task:
    """``doc`` with the fields of a PUT body applied (validated as a whole); ids kept."""
    unknown = sorted(set(body) - _CHANGEABLE)
    if unknown:
        raise DocumentError(f"task: field {unknown[0]!r} cannot be changed; changeable: "
                            "name, loop_flag, sub_tasks, control_type, blackboard")
    merged: dict[str, Any] = {"name": doc.name, "loop_flag": doc.loop_flag,
                              "control_type": doc.control_type, "blackboard": doc.blackboard}
    for k in ("success_count", "target_loop_count"):
        if getattr(doc, k) is not UNSET:
            merged[k] = getattr(doc, k)
    merged["sub_tasks"] = list(doc.sub_tasks)
    merged.update({k: v for k, v in body.items() if k != "id"})
    fresh = new_task(merged)
    fresh.id = doc.id
    fresh.loop_count = doc.loop_count
    if "sub_tasks" not in body:
        fresh.sub_tasks = doc.sub_tasks  # unchanged: same items, same ids
    else:
        _keep_ids(fresh.sub_tasks, body["sub_tasks"], {i.id for i in walk(doc)})
    return fresh


def _keep_ids(items: list[Item], given: list[Any], known: set[str]) -> None:
    """Items of a PUT body that name an id the task already had keep that id."""
    for item, src in zip(items, given, strict=True):
        if isinstance(src, dict):
            ident, subs = src.get("id"), src.get("sub_tasks")
        elif isinstance(src, ActionBase | SubTask):
            ident, subs = src.id, src.sub_tasks if isinstance(src, SubTask) else None
        else:
            continue
        if isinstance(ident, str) and ident in known:
            item.id = ident
        if is_task(item) and isinstance(subs, list):
            _keep_ids(item.sub_tasks, subs, known)


def action_params(item: Action) -> dict[str, Any]:
    """An action's parameters as plain data (no id, state, result or progress)."""
    out: dict[str, Any] = msgspec.to_builtins(item)
    return {k: v for k, v in out.items() if k not in COMMON_FIELDS}


def update_action(item: Action, changes: Mapping[str, Any]) -> Action:
    """``item`` with ``changes`` applied to its parameters (checked against the type once
    merged, which the changes may name); its id kept, its progress reset."""
    merged = {"type": kind_of(item), **action_params(item)}
    merged.update({k: v for k, v in changes.items() if k != "id"})
    fresh = new_action(merged)
    fresh.id = item.id
    return fresh


def _expect(where: str, field: str, value: Any, kind: type) -> None:
    if not isinstance(value, kind) or (kind is not bool and isinstance(value, bool)):
        raise DocumentError(f"{where}: field {field!r} must be {kind.__name__}, got "
                            f"{type(value).__name__}")


def walk(doc: TaskDoc) -> Iterator[Item]:
    """Every item below ``doc`` (not ``doc`` itself), depth first, in execution order."""
    for item in doc.sub_tasks:
        yield item
        if is_task(item):
            yield from walk(item)


def leaves(doc: TaskDoc) -> list[Action]:
    """The actions below ``doc``, in execution order."""
    return [i for i in walk(doc) if not isinstance(i, SubTask)]


def find_item(doc: TaskDoc, item_id: str) -> Item | None:
    """The item with ``item_id`` below ``doc``, or None."""
    return next((i for i in walk(doc) if i.id == item_id), None)


def progress_of(doc: TaskDoc) -> float:
    """Completed fraction of the actions below ``doc``; a running one counts its own part."""
    acts = leaves(doc)
    if not acts:
        return 1.0 if doc.state == COMPLETE else 0.0
    done = sum(1.0 if a.state == COMPLETE else float(a.progress) for a in acts)
    return round(min(1.0, done / len(acts)), 4)


def reset(doc: TaskDoc) -> None:
    """Every item back to WAITTING with no result or progress (a new run or loop)."""
    for item in walk(doc):
        item.state = WAITTING
        item.progress = 0.0
        if isinstance(item, SubTask):
            item.current_task = None
        else:
            item.result = ""
            if item.current_distance is not UNSET:
                item.current_location = Location()
                item.current_distance = -1.0
    doc.progress = 0.0
    doc.current_task = None


def substitute(params: dict[str, Any], board: Mapping[str, Any]) -> dict[str, Any]:
    """``params`` with ``{name}`` in string values replaced by blackboard values (§8.5)."""
    if not board:
        return params
    out = {}
    for k, v in params.items():
        if isinstance(v, str) and "{" in v:
            for name, value in board.items():
                v = v.replace("{" + str(name) + "}", str(value))
        out[k] = v
    return out
