"""``ZENROS_INTERFACE_PATH``: folders of interface packages (each a package, or a folder of
them such as a workspace's ``src/``), ``:``-separated, whose types every zenros tool, node
and bridge finds by name, loaded the first time a name names their package."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import UnknownTypeError
from ..registry import add_package_source
from ..ros2.idl import InterfaceError
from .build import load_interface_package, loaded_packages
from .package import find_packages

__all__ = ["ENV", "INTERFACE_PATH", "InterfacePath", "load_from_path", "path_packages"]

ENV = "ZENROS_INTERFACE_PATH"


def path_packages(path: str | None = None) -> dict[str, Path]:
    """The packages of the path (``ZENROS_INTERFACE_PATH`` unless given), first one of a
    name wins."""
    value = os.environ.get(ENV, "") if path is None else path
    found: dict[str, Path] = {}
    for entry in value.split(os.pathsep):
        if entry and Path(entry).is_dir():
            for name, where in find_packages(entry).items():
                found.setdefault(name, where)
    return found


def load_from_path(package: str, path: str | None = None) -> bool:
    """Load ``package`` from the path if it is there and not loaded yet; True if loaded now.

    Raises:
        UnknownTypeError: the package is on the path but cannot be loaded (the reason named).
    """
    if package in loaded_packages():
        return False
    where = path_packages(path).get(package)
    if where is None:
        return False
    try:
        load_interface_package(where)
    except InterfaceError as exc:
        raise UnknownTypeError(f"package {package} from {where} ({ENV}): {exc}") from exc
    return True


class InterfacePath:
    """``ZENROS_INTERFACE_PATH`` as a `zenros.registry.PackageSource` (read at each lookup of
    an unknown package, so a variable set later counts)."""

    def load(self, package: str) -> bool:
        return load_from_path(package)

    def load_all(self) -> None:
        for package in path_packages():
            load_from_path(package)


INTERFACE_PATH = InterfacePath()
add_package_source(INTERFACE_PATH)
