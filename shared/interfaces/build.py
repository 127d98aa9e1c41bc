"""Interface packages made into zenros types at run time: a msgspec class per structure,
registered with its ROS 2 definition (CDR, RIHS01 hash, type description) and as a service or
action type, so every tool, bridge and node finds it by name."""

from __future__ import annotations

import threading
import typing
from pathlib import Path
from typing import Any

import msgspec

from ..errors import UnknownTypeError
from ..message import TABLES, Message, define_action, define_service, normalize_type_name
from ..registry import lookup_type
from ..ros2.idl import InterfaceError
from ..ros2.registry import register_interface, zenros_class_of
from .package import InterfacePackage, class_name, read_package, struct_order
from .plan import ClassRef, plan_field, uses_bulk
from .spec import StructSpec

__all__ = ["load_interface_package", "loaded_packages", "make_types"]

_LOCK = threading.RLock()
_LOADED: dict[str, Path] = {}


def loaded_packages() -> dict[str, Path]:
    """The packages loaded from disk so far, by name, with the folder each came from."""
    with _LOCK:
        return dict(_LOADED)


def load_interface_package(path: str | Path) -> InterfacePackage:
    """Read the package at ``path`` and make its types (once: loading it again is a no-op).

    Raises:
        InterfaceError: a malformed file, a nested type nobody defines, a package zenros
            ships already, or another folder with the same package name loaded before.
    """
    package = read_package(path)
    with _LOCK:
        before = _LOADED.get(package.name)
        if before is not None:
            if before.resolve() != package.path.resolve():
                raise InterfaceError(f"package {package.name} was loaded from {before} "
                                     f"already; not loading {package.path} too")
            return package
        _LOADED[package.name] = package.path  # first: a lookup while making must not load it
        try:
            make_types([package])
        except BaseException:
            del _LOADED[package.name]
            raise
    return package


def make_types(packages: list[InterfacePackage]) -> dict[str, type[Message]]:
    """Make and register the types of ``packages`` (nested types from zenros's own packages
    or from earlier ones), returning the classes by ROS 2 structure name."""
    for package in packages:
        _check_new(package)
    structs = struct_order([s for p in packages for s in p.structs()])
    ours = {s.ros_name for s in structs}
    for s in structs:  # every nested type found before anything registers
        for f in s.fields:
            if f.type.is_nested and f.type.base not in ours:
                _nested_class(f.type.base, {}, f"{s.ros_name}.{f.name}")
    made: dict[str, type[Message]] = {}
    for interface in (i for p in packages for i in p.interfaces):
        register_interface(interface.name, interface.text)
    for s in structs:
        made[s.ros_name] = _make_class(s, made)
    for interface in (i for p in packages for i in p.interfaces):
        pkg, kind, short = interface.name.split("/")
        parts = [made[s.ros_name] for s in interface.parts]
        if kind == "srv":
            define_service(f"{pkg}/{short}", parts[0], parts[1])
        elif kind == "action":
            define_action(f"{pkg}/{short}", parts[0], parts[1], parts[2])
    return made


def _check_new(package: InterfacePackage) -> None:
    for s in package.structs():
        key = normalize_type_name(f"{package.name}/{class_name(s.ros_name)}")
        if key in TABLES.messages or zenros_class_of(s.ros_name) is not None:
            raise InterfaceError(f"{s.ros_name} is defined already (a package zenros ships, "
                                 "or one loaded before): not loading it again")


def _nested_class(name: str, made: dict[str, type[Message]], where: str) -> type[Message]:
    if name in made:
        return made[name]
    cls = zenros_class_of(name)
    if cls is None:
        try:
            cls = lookup_type(name)
        except UnknownTypeError:
            cls = None
    if cls is None:
        raise InterfaceError(f"{where}: nested type {name} is not defined (load its package "
                             "first, or put both in one folder)")
    return cls


def _make_class(s: StructSpec, made: dict[str, type[Message]]) -> type[Message]:
    fields: list[Any] = []
    for f in s.fields:
        ref = None
        if f.type.is_nested:
            nested = _nested_class(f.type.base, made, f"{s.ros_name}.{f.name}")
            ref = ClassRef(nested, nested.__name__)
        plan = plan_field(f, ref)
        fields.append((plan.name, plan.type, plan.default))
    namespace: dict[str, Any] = {
        "__msgtype__": f"{s.package}/{class_name(s.ros_name)}",
        "__bulk__": uses_bulk(list(s.fields)),
        "__doc__": s.doc or None,
    }
    for c in s.constants:
        namespace[c.name] = c.value
    try:
        made_cls = msgspec.defstruct(
            class_name(s.ros_name), fields, bases=(Message,), kw_only=True,
            namespace=namespace, module=f"zenros.interfaces.loaded.{s.package}")
    except (TypeError, ValueError) as exc:
        raise InterfaceError(f"{s.ros_name}: {exc}") from None
    return typing.cast(type[Message], made_cls)
