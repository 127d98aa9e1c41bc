"""DDS topic types of ROS 2 structures: cyclonedds ``IdlStruct`` classes built from
`zenros.ros2`'s definitions, named ``pkg::msg::dds_::Name_`` as rosidl names them.

The bridge never serializes with these classes (zenros's compiled CDR codec writes and reads
the bytes); cyclonedds needs them for the topic's type name, its key-less layout and its
XTypes type information, which DDS peers compare when they match a reader with a writer.
"""

from __future__ import annotations

import typing
from functools import cache
from typing import Any

from cyclonedds.idl import IdlStruct, make_idl_struct
from cyclonedds.idl import types as idl_types
from zenros.ros2.idl import FieldType, MsgDef
from zenros.ros2.registry import definition
from zenros.ros2.typenames import ros_to_dds

__all__ = ["dds_type", "dds_type_name"]

t: Any = idl_types  # its generic aliases (array[T, n], ...) are not typed as generic

_PRIMS: dict[str, Any] = {
    "bool": bool,
    "byte": t.byte,
    "char": t.uint8,  # rosidl maps char to uint8
    "int8": t.int8,
    "uint8": t.uint8,
    "int16": t.int16,
    "uint16": t.uint16,
    "int32": t.int32,
    "uint32": t.uint32,
    "int64": t.int64,
    "uint64": t.uint64,
    "float32": t.float32,
    "float64": t.float64,
}


def dds_type_name(ros_name: str) -> str:
    """``std_msgs/msg/String`` -> ``std_msgs::msg::dds_::String_``."""
    return ros_to_dds(ros_name)


def _base(ft: FieldType) -> Any:
    if ft.base in _PRIMS:
        return _PRIMS[ft.base]
    if ft.base == "string":
        return t.bounded_str[ft.string_bound] if ft.string_bound else str
    if ft.base == "wstring":
        raise TypeError("wstring is not supported")
    return dds_type(ft.base)


def _annotation(ft: FieldType) -> Any:
    base = _base(ft)
    if ft.kind == "array":
        return t.array[base, ft.size]
    if ft.kind == "bounded":
        return t.sequence[base, ft.size]
    if ft.kind == "sequence":
        return t.sequence[base]
    return base


def _class_name(d: MsgDef) -> str:
    return "_".join(d.name.split("/"))


@cache
def dds_type(ros_name: str) -> type[IdlStruct]:
    """The cached ``IdlStruct`` of a ROS 2 structure (``pkg/msg/Name``, ``pkg/srv/X_Request``);
    raises `zenros.errors.UnknownTypeError` if zenros has no definition of it."""
    d = definition(ros_name)
    fields = {f.name: _annotation(f.type) for f in d.fields}
    cls = make_idl_struct(_class_name(d), dds_type_name(ros_name), fields)
    cls.__idl_annotations__["extensibility"] = "final"
    typing.get_type_hints(cls, include_extras=True)  # fail here, not in the DDS layer
    return cls
