"""Where ROS 2 definitions come from, and which zenros class stands for which ROS 2 type.

Definitions are `definitions`'s .msg texts plus whatever `register_interface` adds; every
service expands into ``_Request``, ``_Response`` and ``_Event`` and every action into its
goal, result, feedback, send-goal and get-result parts, as rosidl generates them. A zenros
type with no ROS 2 definition (``zenros_msgs/...``) gets one derived from its fields
(`derive_definition`): int64/float64 unless the field is bounded (``Annotated[int, Meta]``).
"""

from __future__ import annotations

import sys
import typing
from functools import cache
from typing import Any

import msgspec

from ..errors import UnknownTypeError
from ..message import TABLES, Message, _TypedArray, normalize_type_name
from ..registry import load_package, registered_actions, registered_services, registered_types
from . import definitions
from .idl import (
    EMPTY_FIELD,
    FieldType,
    InterfaceError,
    MsgDef,
    RosField,
    parse_msg,
    split_interface,
)

__all__ = [
    "definition",
    "definition_for_class",
    "derive_definition",
    "register_interface",
    "ros_name_of",
    "zenros_class_of",
]

_DEFS: dict[str, MsgDef] = {}
_LOADED = False


def _add(d: MsgDef) -> None:
    _DEFS[d.name] = d


def _nested(name: str) -> FieldType:
    return FieldType(name)


def _add_service(name: str, request: MsgDef, response: MsgDef) -> None:
    """Register a service's parts and the service type itself (for its hash)."""
    _add(request)
    _add(response)
    _add(MsgDef(f"{name}_Event", (
        RosField("info", _nested("service_msgs/msg/ServiceEventInfo")),
        RosField("request", FieldType(request.name, "bounded", 1)),
        RosField("response", FieldType(response.name, "bounded", 1)),
    )))
    _add(MsgDef(name, (
        RosField("request_message", _nested(request.name)),
        RosField("response_message", _nested(response.name)),
        RosField("event_message", _nested(f"{name}_Event")),
    )))


def register_interface(name: str, text: str) -> None:
    """Add a ROS 2 interface from its .msg, .srv or .action text:
    ``name`` is ``pkg/msg/Name``, ``pkg/srv/Name`` or ``pkg/action/Name``."""
    _load()
    parts = name.strip("/").split("/")
    if len(parts) != 3 or parts[1] not in ("msg", "srv", "action"):
        raise InterfaceError(f"interface name must be pkg/msg|srv|action/Name, got {name!r}")
    kind = parts[1]
    if kind == "msg":
        _add(parse_msg(name, text))
    elif kind == "srv":
        req, resp = split_interface(text, 2)
        _add_service(name, parse_msg(f"{name}_Request", req), parse_msg(f"{name}_Response", resp))
    else:
        goal_t, result_t, feedback_t = split_interface(text, 3)
        goal = parse_msg(f"{name}_Goal", goal_t)
        result = parse_msg(f"{name}_Result", result_t)
        feedback = parse_msg(f"{name}_Feedback", feedback_t)
        for d in (goal, result, feedback):
            _add(d)
        uuid = _nested("unique_identifier_msgs/msg/UUID")
        _add_service(
            f"{name}_SendGoal",
            MsgDef(f"{name}_SendGoal_Request",
                   (RosField("goal_id", uuid), RosField("goal", _nested(goal.name)))),
            MsgDef(f"{name}_SendGoal_Response", (
                RosField("accepted", FieldType("bool")),
                RosField("stamp", _nested("builtin_interfaces/msg/Time")),
            )),
        )
        _add_service(
            f"{name}_GetResult",
            MsgDef(f"{name}_GetResult_Request", (RosField("goal_id", uuid),)),
            MsgDef(f"{name}_GetResult_Response", (
                RosField("status", FieldType("int8")),
                RosField("result", _nested(result.name)),
            )),
        )
        _add(MsgDef(f"{name}_FeedbackMessage",
                    (RosField("goal_id", uuid), RosField("feedback", _nested(feedback.name)))))
        _add(MsgDef(name, (
            RosField("goal", _nested(goal.name)),
            RosField("result", _nested(result.name)),
            RosField("feedback", _nested(feedback.name)),
            RosField("send_goal_service", _nested(f"{name}_SendGoal")),
            RosField("get_result_service", _nested(f"{name}_GetResult")),
            RosField("feedback_message", _nested(f"{name}_FeedbackMessage")),
        )))
    definition.cache_clear()


def _load() -> None:
    global _LOADED
    if _LOADED:
        return
    _LOADED = True
    for name, text in definitions.MESSAGES.items():
        _add(parse_msg(name, text))
    for name, text in definitions.SERVICES.items():
        register_interface(name, text)
    for name, text in definitions.ACTIONS.items():
        register_interface(name, text)


@cache
def definition(name: str) -> MsgDef:
    """The `MsgDef` of a ROS 2 structure type (``pkg/msg/Name``, ``pkg/srv/Name_Request``, ...).

    A zenros-only type (a registered zenros class with no ROS 2 definition) gets a derived one.
    """
    _load()
    if name in _DEFS:
        return _DEFS[name]
    if _module_definitions(name.partition("/")[0]) and name in _DEFS:
        return _DEFS[name]
    cls = zenros_class_of(name)
    if cls is not None:
        return derive_definition(cls)
    raise UnknownTypeError(f"no ROS 2 definition for {name!r}")


_MODULES_READ: set[str] = set()


def _module_definitions(package: str) -> bool:
    """Register the ``ROS_DEFINITIONS`` of the modules holding ``package``'s classes (modules
    `zenros interface generate` wrote); True if any were new."""
    load_package(f"{package}/x")
    added = False
    for key, cls in list(TABLES.messages.items()):
        if key.partition("/")[0] != package or cls.__module__ in _MODULES_READ:
            continue
        _MODULES_READ.add(cls.__module__)
        texts = getattr(sys.modules.get(cls.__module__), "ROS_DEFINITIONS", None)
        if isinstance(texts, dict):
            for iname, text in texts.items():
                if iname not in _DEFS:
                    register_interface(iname, text)
                    added = True
    return added


# ------------------------------------------------------------ zenros class <-> ROS 2 name


def _class_names() -> tuple[dict[type, str], dict[str, type]]:
    """Both maps, rebuilt when a type has registered since (a package loaded on demand)."""
    return _class_names_of(len(TABLES.messages), len(TABLES.services), len(TABLES.actions))


@cache
def _class_names_of(*_sizes: int) -> tuple[dict[type, str], dict[str, type]]:
    to_ros: dict[type, str] = {}
    messages = registered_types()
    for srv in registered_services().values():
        pkg, _, short = srv.name.partition("/")
        to_ros[srv.Request] = f"{pkg}/srv/{short}_Request"
        to_ros[srv.Response] = f"{pkg}/srv/{short}_Response"
        event = messages.get(f"{srv.name}_Event")  # made by zenros.service_events
        if event is not None:
            to_ros[event] = f"{pkg}/srv/{short}_Event"
    for act in registered_actions().values():
        pkg, _, short = act.name.partition("/")
        to_ros[act.Goal] = f"{pkg}/action/{short}_Goal"
        to_ros[act.Result] = f"{pkg}/action/{short}_Result"
        to_ros[act.Feedback] = f"{pkg}/action/{short}_Feedback"
    for name, cls in registered_types().items():
        if cls not in to_ros:
            pkg, _, short = name.partition("/")
            to_ros[cls] = f"{pkg}/msg/{short}"
    return to_ros, {v: k for k, v in to_ros.items()}


def ros_name_of(cls: type[Message]) -> str:
    """The ROS 2 name of a zenros class: ``std_msgs/msg/String``, ``std_srvs/srv/SetBool_Request``."""
    to_ros, _ = _class_names()
    if cls in to_ros:
        return to_ros[cls]
    if not cls.__msgtype__:
        raise UnknownTypeError(f"{cls.__qualname__} has no __msgtype__")
    pkg, _, short = normalize_type_name(cls.__msgtype__).partition("/")
    return f"{pkg}/msg/{short}"


def zenros_class_of(ros_name: str) -> type[Message] | None:
    """The zenros class registered for a ROS 2 structure name, or None (its package's module
    imported first if it is one `zenros.msgs` ships and leaves out: `zenros.registry`)."""
    _, from_ros = _class_names()
    cls: type[Message] | None = from_ros.get(ros_name)
    if cls is None and load_package(ros_name):
        _, from_ros = _class_names()
        cls = from_ros.get(ros_name)
    return cls


# ------------------------------------------------------------ derived definitions

_BOUNDED_INTS = {
    (0, 255): "uint8", (0, 65535): "uint16", (0, 4294967295): "uint32",
    (0, 18446744073709551615): "uint64", (-128, 127): "int8", (-32768, 32767): "int16",
    (-2147483648, 2147483647): "int32",
}
_ARRAY_BASES = {"float32": "float32", "float64": "float64", "int8": "int8", "uint8": "uint8"}


def _derive_base(tp: Any, owner: str) -> tuple[str, bool]:
    """(ROS base type, is a sequence) of one Python annotation."""
    origin = typing.get_origin(tp)
    if origin is typing.Annotated:
        inner, *meta = typing.get_args(tp)
        if inner is int:
            for m in meta:
                if isinstance(m, msgspec.Meta):
                    key = (m.ge, m.le)
                    if key in _BOUNDED_INTS:
                        return _BOUNDED_INTS[key], False
        return _derive_base(inner, owner)
    if origin is list:
        (item,) = typing.get_args(tp)
        base, seq = _derive_base(item, owner)
        if seq:
            raise InterfaceError(f"{owner}: nested lists have no ROS 2 form")
        return base, True
    if origin is typing.Literal:
        values = typing.get_args(tp)
        if all(isinstance(v, str) for v in values):
            return "string", False
    if tp is bool:
        return "bool", False
    if tp is int:
        return "int64", False
    if tp is float:
        return "float64", False
    if tp is str:
        return "string", False
    if tp is bytes:
        return "uint8", True
    if isinstance(tp, type) and issubclass(tp, _TypedArray):
        return _ARRAY_BASES[tp.dtype_().dtype.name], True
    if isinstance(tp, type) and issubclass(tp, Message):
        return ros_name_of(tp), False
    raise InterfaceError(f"{owner}: field type {tp!r} has no ROS 2 form")


def derive_definition(cls: type[Message]) -> MsgDef:
    """A ROS 2 definition for a zenros class that has none: its fields, in order."""
    name = ros_name_of(cls)
    fields = []
    for f in msgspec.structs.fields(cls):
        base, seq = _derive_base(f.type, f"{name}.{f.name}")
        fields.append(RosField(f.name, FieldType(base, "sequence" if seq else "single")))
    return MsgDef(name, tuple(fields) or (EMPTY_FIELD,))


def definition_for_class(cls: type[Message]) -> MsgDef:
    """The ROS 2 definition a zenros class is carried with (standard, or derived)."""
    return definition(ros_name_of(cls))
