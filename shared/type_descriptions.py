"""``~/get_type_description`` on every node (type_description_interfaces/GetTypeDescription),
as ROS 2 nodes serve it from Jazzy on, so that ROS 2 tools (and rclpy through a bridge) fetch
the types a zenros node uses: by name and RIHS01 hash, its REP 2011 description (the type and
every type it references) and, when asked, the interface text zenros holds.

A type is answered when the node uses it now: the message type of one of its publishers or
subscriptions, the service or action type of one of its servers or clients, or a part of one
of those (``pkg/srv/Name_Request``, ``pkg/action/Name_Goal``...). Otherwise, or with another
hash, ``successful`` is false with rclpy's reasons. zenros-only types that have no ROS 2 form
(JSON task documents) have no description.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import msgspec

from .errors import UnknownTypeError
from .graph import Graph
from .message import normalize_type_name
from .msgs.type_description_interfaces import (
    GetTypeDescription,
    GetTypeDescriptionRequest,
    GetTypeDescriptionResponse,
    TypeDescription,
    TypeSource,
)
from .ros2 import definitions
from .ros2.idl import InterfaceError
from .ros2.typehash import type_description, type_hash

__all__ = ["describe_type", "serve_type_descriptions", "types_in_use"]

_KINDS = {"pub": "msg", "sub": "msg", "srv": "srv", "cli": "srv", "act": "action",
          "actc": "action"}
_PARTS = {"srv": ("_Request", "_Response", "_Event"),
          "action": ("_Goal", "_Result", "_Feedback", "_SendGoal", "_GetResult",
                     "_FeedbackMessage")}


def types_in_use(graph: Graph, node: str) -> set[str]:
    """The ROS 2 names of the types ``node``'s endpoints use, their parts included."""
    out: set[str] = set()
    for kind, tokens in graph.endpoints_of(node).items():
        ros_kind = _KINDS[kind]
        for t in tokens:
            pkg, _, short = normalize_type_name(t.type).partition("/")
            if not short:
                continue
            name = f"{pkg}/{ros_kind}/{short}"
            out.add(name)
            out.update(name + part for part in _PARTS.get(ros_kind, ()))
    return out


def _source(name: str) -> TypeSource:
    """The interface text zenros holds for ``name`` (constants and comments are not kept);
    a part rosidl generates (a request, a goal...) is ``implicit``, as rosidl marks it."""
    for encoding, table in (("msg", definitions.MESSAGES), ("srv", definitions.SERVICES),
                            ("action", definitions.ACTIONS)):
        if name in table:
            return TypeSource(type_name=name, encoding=encoding,
                              raw_file_contents=table[name].strip() + "\n")
    return TypeSource(type_name=name, encoding="implicit")


def describe_type(name: str, sources: bool = True) -> tuple[TypeDescription, list[TypeSource]]:
    """The REP 2011 description of ROS 2 type ``name`` and, with ``sources``, the text of it
    and of each type it references. Raises `UnknownTypeError` or `InterfaceError`."""
    desc = msgspec.convert(type_description(name), TypeDescription)
    if not sources:
        return desc, []
    names = [name, *(d.type_name for d in desc.referenced_type_descriptions)]
    return desc, [_source(n) for n in names]


def serve_type_descriptions(node: str, graph: Graph,
                            create_service: Callable[[Any, str, Any], Any]) -> None:
    """Serve ``~/get_type_description`` for node ``node`` (its `create_service`)."""

    def handle(req: GetTypeDescriptionRequest) -> GetTypeDescriptionResponse:
        name = req.type_name
        if name not in types_in_use(graph, node):
            return GetTypeDescriptionResponse(
                failure_reason="Type not currently in use by this node")
        try:
            have = type_hash(name)
            if req.type_hash and req.type_hash != have:
                return GetTypeDescriptionResponse(failure_reason=(
                    f"Type hash {req.type_hash} does not match the type this node uses "
                    f"({have})"))
            desc, srcs = describe_type(name, req.include_type_sources)
        except (UnknownTypeError, InterfaceError) as exc:
            return GetTypeDescriptionResponse(failure_reason=(
                f"{name} has no ROS 2 type description: {exc}"))
        return GetTypeDescriptionResponse(successful=True, type_description=desc,
                                          type_sources=srcs)

    create_service(GetTypeDescription, "~/get_type_description", handle)
