"""rosapi ``TypeDef`` lists of zenros message types, as ``message_details`` answers them."""

from __future__ import annotations

import json
import types
import typing
from typing import Any

import msgspec
from zenros.message import Message, _TypedArray

from .convert import long_type, to_json

__all__ = ["typedefs"]

_ARRAYS = {"Float32Array": "float32", "Float64Array": "float64", "Int8Array": "int8",
           "UInt8Array": "uint8"}
_SCALARS: dict[Any, str] = {bool: "bool", int: "int64", float: "float64", str: "string",
                            bytes: "uint8"}


def _strip(tp: Any) -> Any:
    """``Annotated[int, Meta(...)]`` → ``int``; ``X | None`` → ``X``."""
    if typing.get_origin(tp) is typing.Annotated:
        return typing.get_args(tp)[0]
    if typing.get_origin(tp) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        return _strip(args[0]) if len(args) == 1 else tp
    return tp


def _field(tp: Any) -> tuple[str, int, type[Message] | None]:
    """(ROS field type, array length: -1 scalar / 0 unbounded, nested message class)."""
    tp = _strip(tp)
    if isinstance(tp, type) and issubclass(tp, _TypedArray):
        return _ARRAYS.get(tp.__name__, "float64"), 0, None
    if isinstance(tp, type) and issubclass(tp, Message):
        return long_type(tp.__msgtype__ or tp.__name__), -1, tp
    if typing.get_origin(tp) in (list, tuple):
        args = typing.get_args(tp)
        inner, _, nested = _field(args[0] if args else Any)
        return inner, 0, nested
    if typing.get_origin(tp) is typing.Literal:
        values = typing.get_args(tp)
        return (_SCALARS.get(type(values[0]), "string") if values else "string"), -1, None
    return _SCALARS.get(tp, "string"), -1, None


def _example(value: Any) -> str:
    """A scalar default as rosapi writes it (``0``, ``false``, the string itself); ``{}`` for
    a nested message."""
    if isinstance(value, Message):
        return "{}"
    if isinstance(value, str):
        return value
    return json.dumps(to_json(value) if not isinstance(value, (bool, int, float)) else value)


def typedefs(root: type[Message]) -> list[dict[str, Any]]:
    """The TypeDefs of ``root`` and every message type nested in it, ``root`` first."""
    out: list[dict[str, Any]] = []
    seen: set[type[Message]] = set()
    todo = [root]
    while todo:
        cls = todo.pop(0)
        if cls in seen:
            continue
        seen.add(cls)
        hints = typing.get_type_hints(cls, include_extras=True)
        defaults = cls()
        names, kinds, lengths, examples = [], [], [], []
        for f in msgspec.structs.fields(cls):
            kind, length, nested = _field(hints.get(f.name, f.type))
            names.append(f.name)
            kinds.append(kind)
            lengths.append(length)
            examples.append(_example(getattr(defaults, f.name)) if length < 0 else "[]")
            if nested is not None:
                todo.append(nested)
        consts = {k: v for k, v in vars(cls).items()
                  if k.isupper() and isinstance(v, (bool, int, float, str))}
        out.append({"type": long_type(cls.__msgtype__ or cls.__name__), "fieldnames": names,
                    "fieldtypes": kinds, "fieldarraylen": lengths, "examples": examples,
                    "constnames": list(consts), "constvalues": [str(v) for v in consts.values()]})
    return out
