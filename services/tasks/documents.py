"""Task and action documents (docs/robot-api.md §8.2, §9): creation, walking, progress.

Documents are plain JSON-ready dicts, the shape the REST API returns, so they are stored,
published and served as they are. An item of ``sub_tasks`` is an action (it has ``type``)
or a nested task (it has ``sub_tasks``).
"""

from __future__ import annotations

import uuid
from collections.abc import Iterator
from typing import Any, Final

from .actiontypes import ActionParamsError, validate_params
from .states import COMPLETE, WAITTING

__all__ = [
    "CONTROL_TYPES", "DocumentError", "find_item", "is_task", "leaves", "new_action",
    "new_task", "progress_of", "reset", "substitute", "update_task", "walk",
]

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
MAX_ITEMS: Final = 10_000
MAX_DEPTH: Final = 16


class DocumentError(ValueError):
    """A task or action body that is not valid; the text names the field (HTTP 400)."""


def is_task(item: dict[str, Any]) -> bool:
    """Whether ``item`` is a nested task rather than an action."""
    return "sub_tasks" in item or item.get("type") == "task"


def new_action(body: Any, where: str = "action") -> dict[str, Any]:
    """A fresh action document (new id, WAITTING) from a request body."""
    if not isinstance(body, dict):
        raise DocumentError(f"{where}: expected an object, got {type(body).__name__}")
    try:
        params = validate_params(body, where)
    except ActionParamsError as exc:
        raise DocumentError(str(exc)) from exc
    doc: dict[str, Any] = {"id": str(uuid.uuid4()), "type": body["type"], **params,
                           "state": WAITTING, "result": "", "progress": 0.0}
    if body["type"] == "nav_action":
        doc["current_location"] = {"x": -1.0, "y": -1.0, "theta": -1.0}
        doc["current_distance"] = -1.0
    return doc


def new_task(body: Any, where: str = "task", depth: int = 0,
             counter: list[int] | None = None) -> dict[str, Any]:
    """A fresh task document (new ids, WAITTING everywhere) from a request body."""
    counter = [0] if counter is None else counter
    if not isinstance(body, dict):
        raise DocumentError(f"{where}: expected an object, got {type(body).__name__}")
    if depth > MAX_DEPTH:
        raise DocumentError(f"{where}: tasks nest deeper than {MAX_DEPTH} levels")
    unknown = sorted(set(body) - _TASK_FIELDS)
    if unknown:
        raise DocumentError(f"{where}: unknown field {unknown[0]!r}; task fields: "
                            + ", ".join(sorted(_TASK_FIELDS - {'type'})))
    name = body.get("name", "task")
    loop_flag = body.get("loop_flag", False)
    subs = body.get("sub_tasks", [])
    control = body.get("control_type") or "sequence"
    board = body.get("blackboard", {})
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
    items = []
    for i, sub in enumerate(subs):
        counter[0] += 1
        if counter[0] > MAX_ITEMS:
            raise DocumentError(f"{where}: more than {MAX_ITEMS} sub_tasks in all")
        at = f"{where}.sub_tasks[{i}]"
        if isinstance(sub, dict) and is_task(sub):
            items.append(new_task({k: v for k, v in sub.items() if k != "type"}, at,
                                  depth + 1, counter))
        else:
            items.append(new_action(sub, at))
    doc: dict[str, Any] = {"id": str(uuid.uuid4()), "name": name, "sub_tasks": items,
                           "loop_flag": loop_flag, "loop_count": 0, "state": WAITTING,
                           "progress": 0.0, "current_task": None, "control_type": control,
                           "blackboard": board}
    if extra is not None:
        value = body.get(extra, len(items) if extra == "success_count" else 1)
        if not isinstance(value, int) or isinstance(value, bool) or value < 1:
            raise DocumentError(f"{where}: {extra} must be an integer >= 1, got {value!r}")
        doc[extra] = value
    return doc


def update_task(doc: dict[str, Any], body: dict[str, Any]) -> dict[str, Any]:
    """``doc`` with the fields of a PUT body applied (validated as a whole); ids kept."""
    unknown = sorted(set(body) - {"id", "name", "loop_flag", "sub_tasks", "control_type",
                                  "blackboard", "success_count", "target_loop_count"})
    if unknown:
        raise DocumentError(f"task: field {unknown[0]!r} cannot be changed; changeable: "
                            "name, loop_flag, sub_tasks, control_type, blackboard")
    merged = {k: doc[k] for k in ("name", "loop_flag", "control_type", "blackboard")}
    for k in ("success_count", "target_loop_count"):
        if k in doc:
            merged[k] = doc[k]
    merged["sub_tasks"] = [_as_body(s) for s in doc["sub_tasks"]]
    merged.update({k: v for k, v in body.items() if k != "id"})
    fresh = new_task(merged)
    fresh["id"] = doc["id"]
    fresh["loop_count"] = doc.get("loop_count", 0)
    if "sub_tasks" not in body:
        fresh["sub_tasks"] = doc["sub_tasks"]  # unchanged: same items, same ids
    else:
        _keep_ids(fresh["sub_tasks"], body["sub_tasks"], {i["id"] for i in walk(doc)})
    return fresh


def _keep_ids(items: list[dict[str, Any]], given: list[Any], known: set[str]) -> None:
    """Items of a PUT body that name an id the task already had keep that id."""
    for item, src in zip(items, given, strict=True):
        if isinstance(src, dict):
            if isinstance(src.get("id"), str) and src["id"] in known:
                item["id"] = src["id"]
            if is_task(item) and isinstance(src.get("sub_tasks"), list):
                _keep_ids(item["sub_tasks"], src["sub_tasks"], known)


def _as_body(item: dict[str, Any]) -> dict[str, Any]:
    if is_task(item):
        out = {k: v for k, v in item.items() if k in _TASK_FIELDS - {"id", "state", "progress",
                                                                     "current_task",
                                                                     "loop_count", "type"}}
        out["sub_tasks"] = [_as_body(s) for s in item["sub_tasks"]]
        return out
    return {k: v for k, v in item.items() if k not in ("id", "state", "result", "progress",
                                                        "current_location",
                                                        "current_distance")}


def _expect(where: str, field: str, value: Any, kind: type) -> None:
    if not isinstance(value, kind) or (kind is not bool and isinstance(value, bool)):
        raise DocumentError(f"{where}: field {field!r} must be {kind.__name__}, got "
                            f"{type(value).__name__}")


def walk(doc: dict[str, Any]) -> Iterator[dict[str, Any]]:
    """Every item below ``doc`` (not ``doc`` itself), depth first, in execution order."""
    for item in doc.get("sub_tasks", []):
        yield item
        if is_task(item):
            yield from walk(item)


def leaves(doc: dict[str, Any]) -> list[dict[str, Any]]:
    """The actions below ``doc``, in execution order."""
    return [i for i in walk(doc) if not is_task(i)]


def find_item(doc: dict[str, Any], item_id: str) -> dict[str, Any] | None:
    """The item with ``item_id`` below ``doc``, or None."""
    return next((i for i in walk(doc) if i["id"] == item_id), None)


def progress_of(doc: dict[str, Any]) -> float:
    """Completed fraction of the actions below ``doc``; a running one counts its own part."""
    acts = leaves(doc)
    if not acts:
        return 1.0 if doc.get("state") == COMPLETE else 0.0
    done = sum(1.0 if a["state"] == COMPLETE else float(a.get("progress", 0.0)) for a in acts)
    return round(min(1.0, done / len(acts)), 4)


def reset(doc: dict[str, Any]) -> None:
    """Every item back to WAITTING with no result or progress (a new run or loop)."""
    for item in walk(doc):
        item["state"] = WAITTING
        item["progress"] = 0.0
        if is_task(item):
            item["current_task"] = None
        else:
            item["result"] = ""
            if "current_distance" in item:
                item["current_location"] = {"x": -1.0, "y": -1.0, "theta": -1.0}
                item["current_distance"] = -1.0
    doc["progress"] = 0.0
    doc["current_task"] = None


def substitute(params: dict[str, Any], board: dict[str, Any]) -> dict[str, Any]:
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
