"""A ROS interface file (.msg, .srv or .action) read whole: its structures with their fields'
defaults and their constants, the parts a zenros class needs beyond the wire layout."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from ..ros2.idl import (
    EMPTY_FIELD,
    PRIMITIVES,
    STRINGS,
    FieldType,
    InterfaceError,
    MsgDef,
    RosField,
    declarations,
    parse_type,
    split_interface,
)
from .values import parse_value

__all__ = ["KINDS", "Constant", "FieldSpec", "InterfaceSpec", "StructSpec", "parse_interface"]

KINDS = {"msg": ("",), "srv": ("Request", "Response"), "action": ("Goal", "Result", "Feedback")}
NO_DEFAULT: Any = object()
_CONST_RE = re.compile(r"^[A-Z][A-Z0-9_]*$")
_TYPE_NAME_RE = re.compile(r"^[A-Z][A-Za-z0-9]*$")
_PKG_RE = re.compile(r"^[a-z][a-z0-9_]*$")


@dataclass(frozen=True)
class Constant:
    name: str
    base: str
    value: Any


@dataclass(frozen=True)
class FieldSpec:
    name: str
    type: FieldType
    default: Any = NO_DEFAULT

    @property
    def has_default(self) -> bool:
        return self.default is not NO_DEFAULT


@dataclass(frozen=True)
class StructSpec:
    """One structure: ``ros_name`` is ``pkg/msg/Name`` or ``pkg/srv/Name_Request``..."""

    ros_name: str
    fields: tuple[FieldSpec, ...]
    constants: tuple[Constant, ...]
    doc: str = ""

    @property
    def package(self) -> str:
        return self.ros_name.split("/", 1)[0]

    @property
    def msgdef(self) -> MsgDef:
        return MsgDef(self.ros_name, tuple(RosField(f.name, f.type) for f in self.fields)
                      or (EMPTY_FIELD,))

    def nested(self) -> set[str]:
        """The structure types its fields name (``pkg/msg/Name``)."""
        return {f.type.base for f in self.fields if f.type.is_nested}


@dataclass(frozen=True)
class InterfaceSpec:
    """A whole interface file: ``name`` is ``pkg/msg|srv|action/Name``."""

    name: str
    text: str
    parts: tuple[StructSpec, ...]  # msg: itself; srv: request, response; action: goal...

    @property
    def kind(self) -> str:
        return self.name.split("/")[1]

    @property
    def short(self) -> str:
        return self.name.split("/")[2]


def parse_interface(name: str, text: str) -> InterfaceSpec:
    """Parse a .msg, .srv or .action file's text; ``name`` is ``pkg/kind/Name``."""
    parts = name.strip("/").split("/")
    if len(parts) != 3 or parts[1] not in KINDS:
        raise InterfaceError(f"interface name must be pkg/msg|srv|action/Name, got {name!r}")
    pkg, kind, short = parts
    if not _PKG_RE.match(pkg):
        raise InterfaceError(f"{name}: bad package name {pkg!r} (lower case, digits, '_')")
    if not _TYPE_NAME_RE.match(short):
        raise InterfaceError(f"{name}: bad type name {short!r} (CamelCase)")
    suffixes = KINDS[kind]
    chunks = [text] if kind == "msg" else split_interface(text, len(suffixes))
    structs = tuple(
        parse_struct(f"{pkg}/{kind}/{short}" + (f"_{suffix}" if suffix else ""), chunk)
        for suffix, chunk in zip(suffixes, chunks, strict=True))
    return InterfaceSpec(f"{pkg}/{kind}/{short}", text, structs)


def parse_struct(ros_name: str, text: str) -> StructSpec:
    package = ros_name.split("/", 1)[0]
    fields: list[FieldSpec] = []
    constants: list[Constant] = []
    seen: set[str] = set()
    for d in declarations(ros_name, text):
        where = f"{ros_name} line {d.lineno}"
        try:
            t = parse_type(d.type, package)
        except InterfaceError as exc:
            raise InterfaceError(f"{where}: {exc}") from None
        if d.name in seen:
            raise InterfaceError(f"{where}: {d.name!r} is declared twice")
        seen.add(d.name)
        if d.constant:
            if t.kind != "single" or not (t.base in PRIMITIVES or t.base in STRINGS):
                raise InterfaceError(f"{where}: a constant is a primitive or a string, "
                                     f"not {d.type}")
            if not _CONST_RE.match(d.name):
                raise InterfaceError(f"{where}: constant names are upper case: {d.name!r}")
            constants.append(Constant(d.name, t.base, parse_value(t, d.value, where)))
            continue
        default = parse_value(t, d.value, where) if d.value else NO_DEFAULT
        fields.append(FieldSpec(d.name, t, default))
    return StructSpec(ros_name, tuple(fields), tuple(constants), _leading_comment(text))


def _leading_comment(text: str) -> str:
    """The comment block a .msg file opens with (its description), as plain lines."""
    lines: list[str] = []
    for raw in text.splitlines():
        line = raw.strip()
        if line.startswith("#"):
            lines.append(line.lstrip("#").strip())
        elif line or lines:
            break
    while lines and not lines[-1]:
        lines.pop()
    return "\n".join(lines)
