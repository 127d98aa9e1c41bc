"""A ROS interface package on disk (``msg/*.msg``, ``srv/*.srv``, ``action/*.action``, its
name from ``package.xml`` or the folder), and the order its structures must be made in."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ..ros2.idl import InterfaceError
from .spec import KINDS, InterfaceSpec, StructSpec, parse_interface

__all__ = ["InterfacePackage", "class_name", "find_packages", "read_package", "struct_order"]

_XML_NAME = re.compile(r"<name>\s*([A-Za-z0-9_]+)\s*</name>")


@dataclass(frozen=True)
class InterfacePackage:
    name: str
    path: Path
    interfaces: tuple[InterfaceSpec, ...]

    def structs(self) -> list[StructSpec]:
        return [s for i in self.interfaces for s in i.parts]


def is_package(path: Path) -> bool:
    return path.is_dir() and any((path / kind).is_dir() for kind in KINDS)


def read_package(path: str | Path) -> InterfacePackage:
    """Read every interface file of the package at ``path``."""
    root = Path(path)
    if not is_package(root):
        raise InterfaceError(f"{root}: not an interface package (no msg/, srv/ or action/ "
                             "folder)")
    name = package_name(root)
    interfaces = []
    for kind in KINDS:
        for file in sorted((root / kind).glob(f"*.{kind}")):
            interfaces.append(parse_interface(f"{name}/{kind}/{file.stem}",
                                              file.read_text(encoding="utf-8")))
    if not interfaces:
        raise InterfaceError(f"{root}: no .msg, .srv or .action files")
    return InterfacePackage(name, root, tuple(interfaces))


def find_packages(root: str | Path) -> dict[str, Path]:
    """The interface packages at ``root``: itself if it is one, else its sub-folders that are
    (a workspace's ``src/``, an install's ``share/``), by package name."""
    base = Path(root)
    candidates = [base] if is_package(base) else sorted(p for p in base.glob("*") if is_package(p))
    found: dict[str, Path] = {}
    for path in candidates:
        found.setdefault(package_name(path), path)
    return found


def package_name(path: Path) -> str:
    """The name ``package.xml`` gives, else the folder's."""
    xml = path / "package.xml"
    if xml.is_file():
        m = _XML_NAME.search(xml.read_text(errors="replace"))
        if m:
            return m.group(1)
    return path.resolve().name


def class_name(ros_name: str) -> str:
    """The Python class of a structure: ``Name``, ``NameRequest``, ``NameGoal``..."""
    return ros_name.rsplit("/", 1)[1].replace("_", "")


def struct_order(structs: list[StructSpec]) -> list[StructSpec]:
    """``structs`` with every structure after the ones of this list it nests."""
    by_name = {s.ros_name: s for s in structs}
    done: set[str] = set()
    busy: set[str] = set()
    out: list[StructSpec] = []

    def visit(s: StructSpec) -> None:
        if s.ros_name in done:
            return
        if s.ros_name in busy:
            raise InterfaceError(f"{s.ros_name} nests itself (directly or through others)")
        busy.add(s.ros_name)
        for dep in sorted(s.nested()):
            if dep in by_name:
                visit(by_name[dep])
        busy.discard(s.ros_name)
        done.add(s.ros_name)
        out.append(s)

    for s in structs:
        visit(s)
    return out
