"""ROS messages as rosbags deserialises them (dataclasses with numpy arrays) -> zenros messages,
field by field, for bags recorded with ROS (`zenros.bag.foreign`).

A builder is compiled once per zenros class from its msgspec type information: nested
structures recurse, typed arrays (``float32[]``, ``int8[]``, ``uint8[]``) become zenros's numpy
arrays, ``uint8[]`` typed as bytes becomes bytes, numeric lists become Python lists. Fields
zenros does not have (ROS 1's ``Header.seq``) are ignored and fields the ROS message lacks
keep zenros's default; ROS 1 names that differ only in case (``CameraInfo.K``) are matched.
Times need no special case: rosbags reads ROS 1 ``time``/``duration`` into
builtin_interfaces's ``sec``/``nanosec`` already.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache
from typing import Any

import msgspec.inspect as mi
import numpy as np

from ..message import Message, _TypedArray, to_array

__all__ = ["builder_for", "ros1_alias"]

Builder = Callable[[Any], Message]

# ROS 1 types whose ROS 2 counterpart has another name
_ROS1_ALIASES = {"tf/msg/tfMessage": "tf2_msgs/msg/TFMessage"}


def ros1_alias(ros_name: str) -> str:
    """The ROS 2 name of a ROS 1 type (rosbags already spells it ``pkg/msg/Type``)."""
    return _ROS1_ALIASES.get(ros_name, ros_name)


def _identity(v: Any) -> Any:
    return v


def _to_bytes(v: Any) -> bytes:
    if isinstance(v, np.ndarray):
        return v.tobytes()
    return bytes(v)


def _to_list(v: Any) -> list[Any]:
    if isinstance(v, np.ndarray):
        out: list[Any] = v.tolist()
        return out
    return list(v)


def _converter(t: mi.Type) -> Callable[[Any], Any]:
    """How one field's ROS value becomes the value zenros's field type ``t`` wants."""
    if isinstance(t, mi.StructType):
        return builder_for(t.cls)
    if isinstance(t, mi.CustomType) and issubclass(t.cls, _TypedArray):
        cls = t.cls
        return lambda v: to_array(cls, v)
    if isinstance(t, (mi.BytesType, mi.ByteArrayType)):
        return _to_bytes
    if isinstance(t, (mi.ListType, mi.VarTupleType, mi.TupleType)):
        items = t.item_types[0] if isinstance(t, mi.TupleType) else t.item_type
        if isinstance(items, mi.StructType) or (
                isinstance(items, mi.CustomType) and issubclass(items.cls, _TypedArray)):
            each = _converter(items)
            seq: Callable[[Any], Any] = lambda v: [each(x) for x in v]
        else:
            seq = _to_list
        if isinstance(t, mi.ListType):
            return seq
        return lambda v: tuple(seq(v))
    if isinstance(t, mi.UnionType):
        real = [u for u in t.types if not isinstance(u, mi.NoneType)]
        if len(real) == 1:
            inner = _converter(real[0])
            return lambda v: None if v is None else inner(v)
        return _identity
    if isinstance(t, mi.IntType):
        return int
    if isinstance(t, mi.FloatType):
        return float
    if isinstance(t, mi.BoolType):
        return bool
    return _identity


_CASE_MAPS: dict[type, dict[str, str]] = {}


def _case_map(ros_type: type) -> dict[str, str]:
    """A ROS class's field names by their lower-case spelling."""
    out = _CASE_MAPS.get(ros_type)
    if out is None:
        names: Any = (getattr(ros_type, "__dataclass_fields__", None)
                      or getattr(ros_type, "__slots__", None) or ())
        out = _CASE_MAPS[ros_type] = {n.lower(): n for n in names}
    return out


def _compile(cls: type[Message], parts: list[tuple[str, str, Callable[[Any], Any]]],
             ros_type: type) -> Builder:
    """One constructor call with every field's expression inlined, for one ROS class: its
    attribute names resolved once (case-insensitively where they differ)."""
    names = _case_map(ros_type)
    env: dict[str, Any] = {"cls": cls}
    args = []
    for i, (name, src, conv) in enumerate(parts):
        actual = src if src in names.values() else names.get(src.lower())
        if actual is None or not actual.isidentifier():
            continue  # the ROS type has no such field: zenros's default
        if conv is _identity:
            args.append(f"{name}=o.{actual}")
        else:
            env[f"c{i}"] = conv
            args.append(f"{name}=c{i}(o.{actual})")
    exec(f"def build(o):\n    return cls({', '.join(args)})\n", env)  # noqa: S102  # names checked
    built: Builder = env["build"]
    return built


@cache
def builder_for(cls: type[Message]) -> Builder:
    """The function that makes a ``cls`` from a rosbags message of the same ROS type (a
    constructor compiled per ROS class it meets)."""
    info = mi.type_info(cls)
    assert isinstance(info, mi.StructType)
    parts = [(f.name, f.encode_name, _converter(f.type)) for f in info.fields]
    compiled: dict[type, Builder] = {}

    def build(obj: Any) -> Message:
        fn = compiled.get(type(obj))
        if fn is None:
            fn = compiled[type(obj)] = _compile(cls, parts, type(obj))
        return fn(obj)

    return build
