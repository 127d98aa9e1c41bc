"""The ROS 2 interface model: field types as .msg declares them, parsed from .msg text.

A `MsgDef` is one structure (``pkg/msg/Name``, or a service or action part such as
``pkg/srv/Name_Request``) with its fields in wire order; constants and default values are not
part of the wire layout nor of the type hash, so they are skipped.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Literal

from ..errors import ZenrosError

__all__ = [
    "PRIMITIVES",
    "Declaration",
    "FieldType",
    "InterfaceError",
    "MsgDef",
    "RosField",
    "declarations",
    "parse_msg",
    "split_interface",
]


class InterfaceError(ZenrosError, ValueError):
    """A ROS interface definition is malformed or names an unknown type."""


# name -> (struct format char, size); strings have no fixed size
PRIMITIVES: dict[str, tuple[str, int]] = {
    "bool": ("?", 1),
    "byte": ("B", 1),
    "char": ("B", 1),
    "int8": ("b", 1),
    "uint8": ("B", 1),
    "int16": ("h", 2),
    "uint16": ("H", 2),
    "int32": ("i", 4),
    "uint32": ("I", 4),
    "int64": ("q", 8),
    "uint64": ("Q", 8),
    "float32": ("f", 4),
    "float64": ("d", 8),
}
STRINGS = ("string", "wstring")

Kind = Literal["single", "array", "bounded", "sequence"]

_TYPE_RE = re.compile(
    r"^(?P<base>[A-Za-z][A-Za-z0-9_]*(?:/[A-Za-z][A-Za-z0-9_]*){0,2})"
    r"(?:<=(?P<strbound>\d+))?"
    r"(?:\[(?P<arr>(?:<=)?\d*)\])?$"
)
_NAME_RE = re.compile(r"^[a-z][a-z0-9_]*$")


@dataclass(frozen=True, slots=True)
class FieldType:
    """A field's type: a primitive, ``string``/``wstring`` or a nested ``pkg/msg/Name``,
    single or as a fixed array, a bounded sequence or an unbounded sequence."""

    base: str
    kind: Kind = "single"
    size: int = 0  # array length, or a bounded sequence's maximum
    string_bound: int = 0  # string<=N

    @property
    def is_primitive(self) -> bool:
        return self.base in PRIMITIVES

    @property
    def is_string(self) -> bool:
        return self.base in STRINGS

    @property
    def is_nested(self) -> bool:
        return not (self.is_primitive or self.is_string)

    def __str__(self) -> str:
        s = self.base + (f"<={self.string_bound}" if self.string_bound else "")
        if self.kind == "array":
            s += f"[{self.size}]"
        elif self.kind == "bounded":
            s += f"[<={self.size}]"
        elif self.kind == "sequence":
            s += "[]"
        return s


@dataclass(frozen=True, slots=True)
class RosField:
    name: str
    type: FieldType


@dataclass(frozen=True, slots=True)
class MsgDef:
    """One ROS structure type: ``name`` is ``pkg/msg/Name`` (or ``pkg/srv/Name_Request``...)."""

    name: str
    fields: tuple[RosField, ...]

    @property
    def package(self) -> str:
        return self.name.split("/", 1)[0]


EMPTY_FIELD = RosField("structure_needs_at_least_one_member", FieldType("uint8"))


def _resolve_base(base: str, package: str) -> str:
    if base in PRIMITIVES or base in STRINGS:
        return base
    parts = base.split("/")
    if len(parts) == 1:
        if base == "Header":  # the one implicit name .msg files keep from ROS 1
            return "std_msgs/msg/Header"
        return f"{package}/msg/{base}"
    if len(parts) == 2:
        return f"{parts[0]}/msg/{parts[1]}"
    return base


def parse_type(text: str, package: str) -> FieldType:
    """Parse one .msg field type (``float64[36]``, ``string<=10[<=3]``, ``Pose[]``...)."""
    m = _TYPE_RE.match(text)
    if not m:
        raise InterfaceError(f"bad field type {text!r}")
    base = _resolve_base(m["base"], package)
    strbound = int(m["strbound"]) if m["strbound"] else 0
    if strbound and base not in STRINGS:
        raise InterfaceError(f"only strings take a <= bound: {text!r}")
    arr = m["arr"]
    if arr is None:
        return FieldType(base, "single", 0, strbound)
    if arr == "":
        return FieldType(base, "sequence", 0, strbound)
    if arr.startswith("<="):
        if arr == "<=":
            raise InterfaceError(f"bounded sequence without a bound: {text!r}")
        return FieldType(base, "bounded", int(arr[2:]), strbound)
    return FieldType(base, "array", int(arr), strbound)


@dataclass(frozen=True, slots=True)
class Declaration:
    """One line of .msg text that declares something: a field (``value`` is its default
    value's text, or "") or a constant (``constant`` True, ``value`` its value's text)."""

    lineno: int
    type: str
    name: str
    value: str
    constant: bool


def declarations(name: str, text: str) -> list[Declaration]:
    """The field and constant lines of .msg text, in order (comments and blank lines left out).

    A trailing comment stays in ``value``: only the value's own syntax knows where a string
    ends (`zenros.interfaces.values`)."""
    out: list[Declaration] = []
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        ftype, _, rest = line.replace("\t", " ").partition(" ")
        rest = rest.strip()
        if not rest:
            raise InterfaceError(f"{name} line {lineno}: expected 'type name': {raw!r}")
        head = rest.split(None, 1)[0]
        if "=" in head or rest[len(head):].lstrip().startswith("="):
            cname, _, value = rest.partition("=")
            out.append(Declaration(lineno, ftype, cname.strip(), value.strip(), True))
            continue
        fname = head.split("#", 1)[0]
        value = rest[len(head):].strip() if "#" not in head else ""
        if not _NAME_RE.match(fname):
            raise InterfaceError(f"{name} line {lineno}: bad field name {fname!r}")
        out.append(Declaration(lineno, ftype, fname, "" if value.startswith("#") else value,
                               False))
    return out


def parse_msg(name: str, text: str) -> MsgDef:
    """Parse .msg text into a `MsgDef` named ``name`` (``pkg/msg/Name``); constants and
    defaults are dropped; a structure without fields gets ROS 2's one uint8 member."""
    package = name.split("/", 1)[0]
    fields: list[RosField] = []
    for d in declarations(name, text):
        if d.constant:
            continue
        try:
            fields.append(RosField(d.name, parse_type(d.type, package)))
        except InterfaceError as exc:
            raise InterfaceError(f"{name} line {d.lineno}: {exc}") from None
    return MsgDef(name, tuple(fields) or (EMPTY_FIELD,))


def split_interface(text: str, parts: int) -> list[str]:
    """Split .srv (2 parts) or .action (3 parts) text on its ``---`` lines."""
    chunks: list[list[str]] = [[]]
    for line in text.splitlines():
        if line.strip() == "---":
            chunks.append([])
        else:
            chunks[-1].append(line)
    if len(chunks) != parts:
        raise InterfaceError(f"expected {parts} parts separated by '---', got {len(chunks)}")
    return ["\n".join(c) for c in chunks]
