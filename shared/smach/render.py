"""`render_tree`: a machine's structure and status as indented text, for `zenros smach show`."""

from __future__ import annotations

import json
from typing import Any

from .introspection import ContainerStatus, StateStructure

__all__ = ["render_tree"]

_MAX_VALUE = 60


def render_tree(
    structure: StateStructure, status: ContainerStatus | None = None, *, title: str = ""
) -> str:
    """Draw the tree of states, one line each, with the active ones marked ``*``.

    Each line shows the label, the type, ``[initial]`` where a container starts in some of
    its states only, and the state's edges (``outcome -> next``). A container's userdata
    follows its line.

    Example:
        ``/smach_patrol/smach  StateMachine  running`` then ``|-- * IDLE (MonitorState) ...``

    Args:
        structure: The root's structure.
        status: The root's status; None draws the structure alone.
        title: What to call the machine on the first line (default: its path).
    """
    by_path = _index(status) if status is not None else {}
    lines = [_header(structure, status, title)]
    if status is not None:
        lines += _userdata(status, "    ")
    _draw(structure, by_path, "", lines)
    return "\n".join(lines)


def _index(status: ContainerStatus) -> dict[str, ContainerStatus]:
    found = {status.path: status}
    for child in status.children:
        found.update(_index(child))
    return found


def _header(structure: StateStructure, status: ContainerStatus | None, title: str) -> str:
    if status is None:
        state = "(no status yet)"
    elif status.running:
        state = "running"
    elif status.last_outcome is not None:
        state = f"finished: {status.last_outcome}"
    else:
        state = "idle"
    outcomes = ", ".join(structure.outcomes)
    return f"{title or structure.path}  {structure.type}  {state}  (outcomes: {outcomes})"


def _draw(node: StateStructure, by_path: dict[str, ContainerStatus], prefix: str,
          lines: list[str]) -> None:
    status = by_path.get(node.path)
    active = set(status.active_states) if status is not None and status.running else set()
    initial = node.initial_states if len(node.initial_states) < len(node.children) else []
    last_index = len(node.children) - 1
    for i, child in enumerate(node.children):
        last = i == last_index
        mark = "*" if child.label in active else " "
        text = f"{prefix}{'`-- ' if last else '|-- '}{mark} {child.label} ({child.type})"
        if child.label in initial:
            text += " [initial]"
        edges = [f"{e.outcome} -> {e.target}" for e in node.transitions if e.source == child.label]
        if edges:
            text += "  " + ", ".join(edges)
        if status is not None and mark == "*" and child.is_container:
            index = by_path.get(child.path, status).info.get("index")
            if index is not None and child.type == "Iterator":
                text += f"  (item {index})"
        lines.append(text)
        if child.is_container:
            deeper = prefix + ("    " if last else "|   ")
            child_status = by_path.get(child.path)
            if child_status is not None:
                lines += _userdata(child_status, deeper + "    ")
            _draw(child, by_path, deeper, lines)


def _userdata(status: ContainerStatus, indent: str) -> list[str]:
    items = [f"{k}={_short(v)}" for k, v in status.userdata.items()]
    items += [f"{k}=<{t}>" for k, t in status.unserializable.items()]
    return [f"{indent}userdata: {', '.join(items)}"] if items else []


def _short(value: Any) -> str:
    text = json.dumps(value, separators=(",", ":"), default=str)
    return text if len(text) <= _MAX_VALUE else text[: _MAX_VALUE - 3] + "..."
