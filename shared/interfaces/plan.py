"""How a ROS field is held in a zenros class: the Python type, its default, and both as
source text, for the classes made at run time (`build`) and the modules written (`codegen`)
alike.

- integers are ``int`` (``UInt8``... of `zenros.primitives`: range-checked on decode), floats
  ``float``, bools ``bool``, strings ``str``;
- sequences of byte, char and uint8 are `UInt8Array` (numpy; base64 in JSON, as rosbridge
  sends them; raw bytes in MessagePack, a zero-copy view when received: an image, a point
  cloud), fixed arrays of them ``bytes``; arrays and sequences of float32, float64 and int8
  numpy arrays (`Float32Array`...), of anything else lists;
- a nested structure is its class, default-constructed.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import partial
from typing import Any

import msgspec

from .. import primitives
from ..message import Float32Array, Float64Array, Int8Array, UInt8Array, array_field
from ..ros2.idl import PRIMITIVES
from .spec import FieldSpec

__all__ = ["ClassRef", "FieldPlan", "plan_field", "source", "uses_bulk"]

_TYPED_ARRAYS: dict[str, Any] = {"float32": Float32Array, "float64": Float64Array,
                                 "int8": Int8Array, "uint8": UInt8Array, "byte": UInt8Array,
                                 "char": UInt8Array}


@dataclass(frozen=True)
class ClassRef:
    """A nested structure's class: the object (at run time) and the name code uses."""

    obj: Any
    src: str


@dataclass(frozen=True)
class FieldPlan:
    name: str
    type: Any  # the annotation object
    type_src: str
    default: Any  # a value, or a msgspec field with a default factory
    default_src: str
    imports: frozenset[str]  # names of zenros.message / zenros.primitives the source uses


def _scalar(base: str, prefix: str) -> tuple[Any, str, frozenset[str]]:
    if base == "bool":
        return bool, "bool", frozenset()
    if base in ("float32", "float64"):
        return float, "float", frozenset()
    if base in ("string", "wstring"):
        return str, "str", frozenset()
    alias = primitives.int_alias(base)
    return getattr(primitives, alias), prefix + alias, frozenset({alias})


def source(value: Any) -> str:
    """Python source of a default value, in the project's style (double quotes)."""
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, bytes):
        return f"bytes({len(value)})" if not any(value) else repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(source(v) for v in value) + "]"
    return repr(value)


def _zero(base: str) -> Any:
    if base == "bool":
        return False
    if base in ("float32", "float64"):
        return 0.0
    if base in ("string", "wstring"):
        return ""
    return 0


def _source_only() -> Any:
    raise TypeError("a plan made for source code has no class to construct")


def _instances(cls: Any, n: int) -> list[Any]:
    return [cls() for _ in range(n)]


def plan_field(f: FieldSpec, nested: ClassRef | None, alias_prefix: str = "") -> FieldPlan:
    """The plan of one field; ``nested`` is the class of a nested structure field;
    ``alias_prefix`` goes before `zenros.primitives`'s names in the source."""
    t = f.type
    if t.is_nested:
        assert nested is not None
        if nested.obj is None:  # source only (codegen): no class to call
            nested = ClassRef(_source_only, nested.src)
        if t.kind == "single":
            return FieldPlan(f.name, nested.obj, nested.src,
                             msgspec.field(default_factory=nested.obj),
                             f"msgspec.field(default_factory={nested.src})", frozenset())
        if t.kind == "array":
            return FieldPlan(
                f.name, list[nested.obj], f"list[{nested.src}]",  # type: ignore[name-defined]
                msgspec.field(default_factory=partial(_instances, nested.obj, t.size)),
                f"msgspec.field(default_factory=lambda: [{nested.src}() "
                f"for _ in range({t.size})])", frozenset())
        return FieldPlan(f.name, list[nested.obj], f"list[{nested.src}]",  # type: ignore[name-defined]
                         msgspec.field(default_factory=list),
                         "msgspec.field(default_factory=list)", frozenset())
    scalar, scalar_src, names = _scalar(t.base, alias_prefix)
    if t.kind == "single":
        value = f.default if f.has_default else _zero(t.base)
        return FieldPlan(f.name, scalar, scalar_src, value, source(value), names)
    values: list[Any] = (list(f.default) if f.has_default
                         else [_zero(t.base)] * t.size if t.kind == "array" else [])
    if t.is_primitive and PRIMITIVES[t.base][0] == "B" and t.kind == "array":
        data = bytes(values)  # a fixed handful of bytes (a UUID, a gid)
        return FieldPlan(f.name, bytes, "bytes", data, source(data), frozenset())
    typed = _TYPED_ARRAYS.get(t.base)
    if typed is not None:
        name = typed.__name__
        src_values = f", {source(values)}" if values else ""
        return FieldPlan(f.name, typed, name, array_field(typed, values),
                         f"array_field({name}{src_values})",
                         frozenset({name, "array_field"}))
    list_type = list[scalar]  # type: ignore[valid-type]
    if values:
        return FieldPlan(f.name, list_type, f"list[{scalar_src}]",
                         msgspec.field(default_factory=partial(list, values)),
                         f"msgspec.field(default_factory=lambda: {source(values)})", names)
    return FieldPlan(f.name, list_type, f"list[{scalar_src}]",
                     msgspec.field(default_factory=list),
                     "msgspec.field(default_factory=list)", names)


def uses_bulk(fields: list[FieldSpec]) -> bool:
    """Sent as MessagePack (``__bulk__``): a structure with a byte sequence (an image, a
    point cloud, compressed data), which JSON would carry as base64."""
    return any(f.type.kind in ("sequence", "bounded") and f.type.is_primitive
               and PRIMITIVES[f.type.base][0] == "B" for f in fields)
