"""ROS 2 tutorial action types a rosbridge client may name for an action zenros serves in
another package's type with the same layout (``action_tutorials_interfaces/action/Fibonacci``
for the sim's ``example_interfaces/action/Fibonacci``, as roslibjs's ROS 2 examples do).

The goal goes to the zenros server in its own type; feedback and result come back in the type
the client named, field by field in order (``sequence`` is sent as ``partial_sequence``), as a
server of the client's type would send them. Used only when the two types' Goal, Result and
Feedback have the same field types in the same order, and only while the graph lists the
action with the other type and not with the client's.
"""

from __future__ import annotations

from typing import Any, TypeVar

import msgspec
import zenros.msgs.action_tutorials_interfaces  # noqa: F401 (registers the tutorial type)
from zenros.message import ActionType, Message, normalize_type_name
from zenros.registry import lookup_action

__all__ = ["ROS2_EQUIVALENTS", "convert", "served_type"]

ROS2_EQUIVALENTS = {"action_tutorials_interfaces/Fibonacci": "example_interfaces/Fibonacci"}
"""A tutorial action type -> the type of the same layout zenros's example servers use."""

M = TypeVar("M", bound=Message)


def _types(cls: type[Message]) -> list[Any]:
    return [f.type for f in msgspec.structs.fields(cls)]


def _agree(a: ActionType, b: ActionType) -> bool:
    return all(_types(x) == _types(y) for x, y in
               ((a.Goal, b.Goal), (a.Result, b.Result), (a.Feedback, b.Feedback)))


def served_type(requested: ActionType, graph_types: list[str]) -> ActionType:
    """The type to send a goal of ``requested`` in, given the types the graph lists for the
    action: ``requested`` itself, unless only its equivalent is served."""
    served = {normalize_type_name(t) for t in graph_types}
    other = ROS2_EQUIVALENTS.get(requested.name)
    if other is None or requested.name in served or other not in served:
        return requested
    other_type = lookup_action(other)
    return other_type if _agree(requested, other_type) else requested


def convert(msg: Message, to: type[M]) -> M:
    """``msg`` as ``to`` (a type of the same layout), field by field in order."""
    if type(msg) is to:
        return msg
    names = [f.name for f in msgspec.structs.fields(to)]
    values = [getattr(msg, f.name) for f in msgspec.structs.fields(type(msg))]
    return to(**dict(zip(names, values, strict=True)))
