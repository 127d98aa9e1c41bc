"""`generate_module`: the Python source of a zenros module for an interface package, as
rosidl generates Python for ROS 2: a class per structure, a service or action type per .srv
and .action, and the ROS 2 texts (``ROS_DEFINITIONS``) that CDR and the type hashes read.

The module imports nothing but zenros and the modules of the packages it nests types from:
``zenros.msgs.<pkg>`` for a package zenros ships, ``<pkg>`` (a module generated alike, on the
import path) for any other.
"""

from __future__ import annotations

import importlib.util
import json
import keyword
import textwrap
from dataclasses import dataclass, field

from ..msgs import __name__ as MSGS
from ..ros2.idl import InterfaceError
from ..ros2.registry import zenros_class_of
from .package import InterfacePackage, class_name, struct_order
from .plan import ClassRef, plan_field, source, uses_bulk
from .spec import StructSpec

__all__ = ["definition_text", "generate_module"]

_PRIMITIVE_NAMES = {"Byte", "Char", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32",
                    "Int64", "UInt64"}
_HEADER = '"""{pkg}: made by `zenros interface generate` from its {files}."""'


@dataclass
class _Imports:
    """What the module imports, each name once (another package's ``Point`` beside a local
    ``Point`` is imported as ``geometry_msgs_Point``)."""

    local: set[str]
    relative: bool
    message: set[str] = field(default_factory=lambda: {"Message"})
    primitives: set[str] = field(default_factory=set)
    modules: dict[str, dict[str, str]] = field(default_factory=dict)  # module -> name -> alias
    msgspec: bool = False
    classvar: bool = False

    @property
    def qualified(self) -> bool:
        """`zenros.primitives`'s names are written ``primitives.UInt8`` (a package with a
        ``UInt8`` message of its own, as std_msgs)."""
        return bool(self.local & _PRIMITIVE_NAMES)

    def nested(self, ros_name: str, pkg: str) -> str:
        """The name the module uses for the class of a nested structure from elsewhere."""
        cls = zenros_class_of(ros_name)
        if cls is not None and (cls.__module__.startswith(f"{MSGS}.")
                                or not cls.__module__.startswith("zenros.")):
            module, name = cls.__module__, cls.__name__
        elif _shipped(pkg):
            raise InterfaceError(f"{ros_name}: zenros ships {pkg} but has no such type")
        else:
            module, name = pkg, class_name(ros_name)
        names = self.modules.setdefault(module, {})
        if name not in names:
            taken = self.local | {a for m in self.modules.values() for a in m.values()}
            names[name] = name if name not in taken else f"{pkg}_{name}"
        return names[name]

    def lines(self) -> list[str]:
        out = ["from __future__ import annotations", ""]
        if self.classvar:
            out += ["from typing import ClassVar", ""]
        if self.msgspec:
            out += ["import msgspec", ""]
        base = ".." if self.relative else "zenros."
        block = [(f"{base}message", _names(self.message))]
        if self.primitives and self.qualified:
            block.append(("..", "primitives") if self.relative else ("zenros", "primitives"))
        elif self.primitives:
            block.append((f"{base}primitives", _names(self.primitives)))
        for module in sorted(self.modules):
            names = ", ".join(n if a == n else f"{n} as {a}"
                              for n, a in sorted(self.modules[module].items()))
            if self.relative and module.startswith(f"{MSGS}."):
                module = "." + module[len(MSGS) + 1:]
            block.append((module, names))
        lines = [_wrap(f"from {m} import ", names) for m, names in sorted(block)]
        return out + [line for group in lines for line in group]


def _names(names: set[str]) -> str:
    """Imported names in isort's order: constants, classes, then functions."""
    return ", ".join(sorted(names, key=lambda n: (0 if n.isupper() else 1 if n[0].isupper()
                                                  else 2, n)))


def _wrap(head: str, items: str) -> list[str]:
    """``head + items`` on one line, or in parentheses one item a line when too long."""
    if len(head) + len(items) <= 99:
        return [head + items]
    return [head + "(", *(f"    {item}," for item in items.split(", ")), ")"]


def _shipped(pkg: str) -> bool:
    return importlib.util.find_spec(f"{MSGS}.{pkg}") is not None


def generate_module(package: InterfacePackage, *, relative: bool = False,
                    only: set[str] | None = None, definitions: bool = True) -> str:
    """The module's source. ``relative`` writes it as a module of `zenros.msgs` (imports
    relative to it); ``only`` limits it to those interfaces; ``definitions=False`` leaves
    ``ROS_DEFINITIONS`` out (zenros's own packages keep theirs in `zenros.ros2.definitions`)."""
    interfaces = [i for i in package.interfaces if only is None or i.name in only]
    structs = struct_order([s for i in interfaces for s in i.parts])
    local = {class_name(s.ros_name) for s in structs}
    imports = _Imports(local, relative)
    bodies = [_class_source(s, local, imports) for s in structs]
    types: list[str] = []
    type_names: list[str] = []
    for i in interfaces:
        if i.kind == "msg":
            continue
        define = "define_service" if i.kind == "srv" else "define_action"
        imports.message.add(define)
        # test_msgs has an Arrays message and an Arrays service: the type gets a suffix
        name = i.short if i.short not in local else i.short + (
            "Service" if i.kind == "srv" else "Action")
        type_names.append(name)
        parts = ", ".join(class_name(s.ros_name) for s in i.parts)
        line = f'{name} = {define}("{package.name}/{i.short}", {parts})'
        if len(line) > 99:
            line = f'{name} = {define}(\n    "{package.name}/{i.short}", {parts})'
        types.append(line)
    kinds = sorted({f".{i.kind}" for i in interfaces})
    exported = sorted(local | set(type_names))
    out = [_HEADER.format(pkg=package.name, files="/".join(kinds) + " files"), ""]
    out += imports.lines()
    with_defs = definitions
    names = ["ROS_DEFINITIONS", *exported] if with_defs else exported
    one_line = "__all__ = [" + ", ".join(json.dumps(n) for n in names) + "]"
    out += ["", one_line] if len(one_line) <= 99 else [
        "", "__all__ = [", *(f"    {json.dumps(n)}," for n in names), "]"]
    out.append("")
    if with_defs:
        out.append("ROS_DEFINITIONS: dict[str, str] = {")
        for i in interfaces:
            text = definition_text(i.text).split("\n")
            out.append(f"    {json.dumps(i.name)}: (")
            out += [f"        {json.dumps(line + chr(10) * (k < len(text) - 1), ensure_ascii=False)}"
                    for k, line in enumerate(text)]
            out.append("    ),")
        out += ["}", ""]
    for body in bodies:
        out += ["", *body, ""]
    if types:
        out += ["", *types]
    return "\n".join(out).rstrip() + "\n"


def definition_text(text: str) -> str:
    """The interface text without comments and blank lines (what the wire and hash need)."""
    keep = []
    for raw in text.splitlines():
        line = raw.strip()
        if line == "---" or (line and not line.startswith("#")):
            keep.append(line)
    return "\n".join(keep)


def _class_source(s: StructSpec, local: set[str], imports: _Imports) -> list[str]:
    name = class_name(s.ros_name)
    lines = [f"class {name}(Message):"]
    if s.doc:
        text = s.doc.replace("\\", "\\\\").replace('"""', "'''")
        doc = [w for line in text.split("\n") for w in (textwrap.wrap(line, 90) or [""])]
        if len(doc) == 1:
            lines.append(f'    """{doc[0]}"""')
        else:
            lines.append(f'    """{doc[0]}')
            lines += [f"    {line}" if line else "" for line in doc[1:]]
            lines.append('    """')
        lines.append("")
    lines.append(f'    __msgtype__ = "{s.package}/{name}"')
    if uses_bulk(list(s.fields)):
        lines.append("    __bulk__ = True")
    for c in s.constants:
        imports.classvar = True
        py = {"bool": "bool", "float32": "float", "float64": "float", "string": "str",
              "wstring": "str"}.get(c.base, "int")
        lines.append(f"    {c.name}: ClassVar[{py}] = {source(c.value)}")
    for f in s.fields:
        if keyword.iskeyword(f.name):
            raise InterfaceError(f"{s.ros_name}: field {f.name!r} is a Python keyword")
        ref = None
        if f.type.is_nested:
            nested = class_name(f.type.base)
            same = f.type.base.split("/", 1)[0] == s.package  # in this module
            src = nested if same else imports.nested(f.type.base, f.type.base.split("/", 1)[0])
            ref = ClassRef(None, src)
        plan = plan_field(f, ref, "primitives." if imports.qualified else "")
        imports.message |= {n for n in plan.imports if n.endswith("Array") or n == "array_field"}
        imports.primitives |= {n for n in plan.imports if not (n.endswith("Array")
                                                                or n == "array_field")}
        imports.msgspec |= "msgspec." in plan.default_src
        lines.append(f"    {f.name}: {plan.type_src} = {plan.default_src}")
    return lines
