"""The loader's position in a launch file, and typed field readers that name file and key."""

from __future__ import annotations

import os
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import InvalidNameError, LaunchError
from ..names import join, validate_namespace
from .substitution import Scope, parse_bool, substitute

__all__ = ["Context"]

_ARG = re.compile(r"\$\(\s*arg\s+([A-Za-z_][A-Za-z0-9_]*)\s*\)")


@dataclass
class Context:
    """Where the loader is: file scope, namespace, inherited env, include chain.

    Its readers parse one field each and fail with the file and the key path.
    """

    scope: Scope
    namespace: str = "/"
    env: dict[str, str] = field(default_factory=dict)
    stack: tuple[Path, ...] = ()

    def fail(self, where: str, why: str) -> LaunchError:
        return self.scope.fail(where, why)

    def text(self, raw: Any, where: str) -> str:
        """A scalar field as a string, after substitution."""
        if isinstance(raw, bool) or not isinstance(raw, (str, int, float)):
            raise self.fail(where, f"expected a string, got {type(raw).__name__} {raw!r}")
        return substitute(str(raw), self.scope, where)

    def words(self, raw: Any, where: str) -> list[str]:
        """A command line: a list of scalars, or one string split as a shell would."""
        if isinstance(raw, str):
            return shlex.split(self.text(raw, where))
        if isinstance(raw, list):
            return [self.text(v, f"{where}[{i}]") for i, v in enumerate(raw)]
        raise self.fail(where, f"expected a list or a string, got {type(raw).__name__}")

    def mapping(self, raw: Any, where: str) -> dict[str, Any]:
        if raw is None:
            return {}
        if not isinstance(raw, dict) or not all(isinstance(k, str) for k in raw):
            raise self.fail(where, f"expected a mapping with string keys, got {raw!r}")
        return raw

    def items(self, raw: Any, where: str) -> list[Any]:
        if raw is None:
            return []
        if not isinstance(raw, list):
            raise self.fail(where, f"expected a list, got {type(raw).__name__}")
        return raw

    def keys(self, raw: dict[str, Any], valid: tuple[str, ...], where: str) -> None:
        for key in raw:
            if key not in valid:
                at = f"{where}.{key}".lstrip(".")
                raise self.fail(at, f"unknown key; valid: {', '.join(valid)}")

    def path(self, raw: Any, where: str) -> Path:
        """A path relative to the current file's directory; must exist."""
        path = Path(os.path.expanduser(self.text(raw, where)))
        path = path if path.is_absolute() else self.scope.file.parent / path
        if not path.exists():
            raise self.fail(where, f"no such file: {path}{self.origin(raw)}")
        return path

    def namespace_for(self, raw: Any, where: str) -> str:
        """A relative namespace joins the current one; an absolute one replaces it."""
        ns = self.text(raw, where)
        try:
            if ns.startswith("/"):
                return validate_namespace(ns)
            return validate_namespace(join(self.namespace, ns.strip("/"))) if ns else self.namespace
        except InvalidNameError as exc:
            first = str(exc).splitlines()[0]
            raise self.fail(where, f"{first}{self.origin(raw)}") from exc

    def origin(self, raw: Any) -> str:
        """`` (from robot:=2bad)`` for the arguments a field's raw text uses, or ``""``: an
        error in a value built from arguments names the argument to change."""
        used = [m.group(1) for m in _ARG.finditer(str(raw)) if m.group(1) in self.scope.args]
        return f" (from {', '.join(f'{n}:={self.scope.args[n]}' for n in used)})" if used else ""

    def environment(self, raw: Any, where: str) -> dict[str, str]:
        m = self.mapping(raw, where)
        return {**self.env, **{k: self.text(v, f"{where}.{k}") for k, v in m.items()}}

    def enabled(self, entry: dict[str, Any], where: str) -> bool:
        """The ``if``/``unless`` conditions of an entry."""
        if "if" in entry and not parse_bool(entry["if"], self.scope, f"{where}.if"):
            return False
        unless = entry.get("unless", False)
        return not parse_bool(unless, self.scope, f"{where}.unless")
