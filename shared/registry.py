"""Message, service and action types by ROS name, the standard types (`zenros.msgs`) included.

`zenros.message` holds the tables types register in as they are defined; this module sits
above `zenros.msgs` and imports it, so a lookup always sees the standard types and
`zenros.message` never imports the messages defined on it.

Every package zenros ships is a module of `zenros.msgs`; most are imported with it, and the
rest (``test_msgs``, ``action_tutorials_interfaces``: their ``Fibonacci`` would make the short
name ambiguous) are imported the first time a lookup names their package
(``test_msgs/action/Fibonacci``), so every shipped type resolves by its ROS 2 name with no
flag; so do the packages of ``ZENROS_INTERFACE_PATH`` (.msg/.srv/.action files made into
types by `zenros.interfaces`). Short names resolve among the packages imported with `zenros.msgs` (and whatever else
registered) first, so loading a package on demand never makes a short name ambiguous.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
from functools import cache
from typing import Any, Protocol, TypeVar

from . import msgs
from .errors import UnknownTypeError
from .message import TABLES, ActionType, Message, ServiceType, find_registered, normalize_type_name

__all__ = ["PackageSource", "add_package_source", "load_all_packages", "load_package", "lookup_action", "lookup_service", "lookup_type",
           "registered_actions", "registered_services", "registered_types"]

T = TypeVar("T")


@cache
def _on_demand() -> frozenset[str]:
    """The packages of `zenros.msgs` that importing it leaves out (imported by name on demand)."""
    return frozenset(info.name for info in pkgutil.iter_modules(msgs.__path__)
                     if info.name not in msgs.__all__)


def load_package(name: str) -> bool:
    """Import the `zenros.msgs` module of the package a type name names (``test_msgs`` for
    ``test_msgs/action/Fibonacci`` or ``test_msgs/action/Fibonacci_Goal``), if it is one that
    importing `zenros.msgs` leaves out and it is not imported yet. True if it was imported now.

    Only the modules `zenros.msgs` ships are ever imported (the name is matched against them,
    never imported as given)."""
    pkg = normalize_type_name(name).partition("/")[0]
    if pkg not in _on_demand():
        return any(source.load(pkg) for source in _SOURCES)
    module = f"{msgs.__name__}.{pkg}"
    if module in sys.modules:
        return False
    importlib.import_module(module)
    return True


def load_all_packages() -> None:
    """Import every package `zenros.msgs` ships (those left out on import too) and load those
    of every `PackageSource` (``ZENROS_INTERFACE_PATH``): for listings that must name every
    type (`zenros interface list`)."""
    for pkg in sorted(_on_demand()):
        module = f"{msgs.__name__}.{pkg}"
        if module not in sys.modules:
            importlib.import_module(module)
    for source in _SOURCES:
        source.load_all()


class PackageSource(Protocol):
    """Where packages zenros does not ship come from (`zenros.interfaces`'s
    ``ZENROS_INTERFACE_PATH``), registered with `add_package_source`."""

    def load(self, package: str) -> bool:
        """Make ``package``'s types if this source has it and it is not loaded; True if now."""
        ...

    def load_all(self) -> None:
        """Make the types of every package this source has."""
        ...


_SOURCES: list[PackageSource] = []


def add_package_source(source: PackageSource) -> None:
    """Have lookups of unknown packages ask ``source`` too."""
    if source not in _SOURCES:
        _SOURCES.append(source)


@cache
def _short_name_limits() -> dict[str, frozenset[str]]:
    """Packages whose module limits what their short names may mean (``SHORT_NAMES``:
    example_interfaces restates std_msgs and std_srvs, so a short ``String`` or ``SetBool``
    keeps meaning the standard one)."""
    out: dict[str, frozenset[str]] = {}
    for name in msgs.__all__:
        limit = getattr(getattr(msgs, name), "SHORT_NAMES", None)
        if limit is not None:
            out[name] = frozenset(limit)
    return out


def _preferred(table: dict[str, T]) -> dict[str, T]:
    """``table`` without the packages loaded on demand (where short names look first), and
    without the types a package keeps out of short names."""
    lazy, limits = _on_demand(), _short_name_limits()
    out = {}
    for key, value in table.items():
        pkg, _, short = key.partition("/")
        if pkg not in lazy and (pkg not in limits or short in limits[pkg]):
            out[key] = value
    return out


def _find(table: dict[str, Any], kind: str, name: str) -> Any:
    if "/" not in normalize_type_name(name):
        try:
            return find_registered(_preferred(table), kind, name)
        except UnknownTypeError:
            pass
    try:
        return find_registered(table, kind, name)
    except UnknownTypeError:
        if not load_package(name):
            raise
    return find_registered(table, kind, name)


def lookup_type(name: str) -> type[Message]:
    """The message class registered under a ROS type name (``pkg/Name``, ``pkg/msg/Name`` or
    an unambiguous ``Name``), its package's module imported if it is one `zenros.msgs` ships
    and leaves out.

    Raises:
        UnknownTypeError: No such type (the message names the closest ones), or a short
            name more than one package defines.
    """
    cls: type[Message] = _find(TABLES.messages, "message", name)
    return cls


def lookup_service(name: str) -> ServiceType:
    """The service type registered under a ROS type name (as `lookup_type`)."""
    srv: ServiceType = _find(TABLES.services, "service", name)
    return srv


def lookup_action(name: str) -> ActionType:
    """The action type registered under a ROS type name (as `lookup_type`)."""
    act: ActionType = _find(TABLES.actions, "action", name)
    return act


def registered_types() -> dict[str, type[Message]]:
    """Every registered message class, by wire type name."""
    return dict(TABLES.messages)


def registered_services() -> dict[str, ServiceType]:
    """Every registered service type, by wire type name."""
    return dict(TABLES.services)


def registered_actions() -> dict[str, ActionType]:
    """Every registered action type, by wire type name."""
    return dict(TABLES.actions)
