"""Launch-file substitutions: ``$(arg x)``, ``$(env X [default])``, ``$(optenv ...)``,
``$(dirname)`` and ``$(expr ...)`` (`expr`: comparisons and logic over the arguments)."""

from __future__ import annotations

import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from ..errors import LaunchError
from .expr import ExprError, evaluate

__all__ = ["Scope", "parse_bool", "spans", "substitute", "substitute_value"]

_KINDS = "arg NAME, env NAME [DEFAULT], optenv NAME [DEFAULT], dirname, expr EXPRESSION"
_QUOTE = re.compile(r"'[^']*'|\"[^\"]*\"")


@dataclass(frozen=True)
class Scope:
    """What substitutions in one launch file see: its arguments, its path, the environment."""

    file: Path
    args: Mapping[str, str] = field(default_factory=dict)
    environ: Mapping[str, str] = field(default_factory=lambda: dict(os.environ))

    def fail(self, where: str, why: str) -> LaunchError:
        """A LaunchError naming this file and the key path ``where``."""
        return LaunchError(f"{self.file}: {where}: {why}" if where else f"{self.file}: {why}")


def _one(scope: Scope, body: str, where: str) -> str:
    kind, _, rest = body.strip().partition(" ")
    words = rest.split(None, 1)
    if kind == "arg" and len(words) == 1:
        name = words[0]
        if name not in scope.args:
            known = ", ".join(scope.args) or "none"
            raise scope.fail(where, f"$(arg {name}): no such argument; declared: {known}")
        return scope.args[name]
    if kind in ("env", "optenv") and words:
        name, default = words[0], (words[1] if len(words) > 1 else None)
        if name in scope.environ:
            return scope.environ[name]
        if default is not None or kind == "optenv":
            return default or ""
        raise scope.fail(
            where, f"$(env {name}): environment variable {name} is not set and has no default"
        )
    if kind == "dirname" and not words:
        return str(scope.file.parent)
    if kind == "expr" and words:
        try:
            return evaluate(rest, scope.args)
        except ExprError as exc:
            raise scope.fail(where, f"$({body.strip()}): {exc}") from exc
    raise scope.fail(where, f"unknown substitution $({body}); valid: {_KINDS}")


def spans(text: str) -> list[tuple[int, int]]:
    """Where each ``$(...)`` of ``text`` starts and ends; parentheses inside balance (as in
    ``$(expr not (a or b))``) and quoted strings inside are skipped. An unclosed ``$(`` is
    left as text."""
    out: list[tuple[int, int]] = []
    pos = 0
    while (start := text.find("$(", pos)) >= 0:
        depth, i = 0, start + 1
        end = -1
        while i < len(text):
            ch = text[i]
            if ch in "'\"" and (m := _QUOTE.match(text, i)) is not None:
                i = m.end()
                continue
            if ch == "(":
                depth += 1
            elif ch == ")":
                depth -= 1
                if depth == 0:
                    end = i + 1
                    break
            i += 1
        if end < 0:
            break
        out.append((start, end))
        pos = end
    return out


def substitute(text: str, scope: Scope, where: str) -> str:
    """Replace every ``$(...)`` in ``text``.

    Raises:
        LaunchError: an unknown substitution, argument or unset variable, or a bad
            expression (names file and key).
    """
    parts, pos = [], 0
    for start, end in spans(text):
        parts += [text[pos:start], _one(scope, text[start + 2:end - 1], where)]
        pos = end
    return "".join([*parts, text[pos:]])


def _whole(text: str) -> bool:
    """Whether ``text`` is exactly one substitution (surrounding blanks aside)."""
    stripped = text.strip()
    found = spans(stripped)
    return len(found) == 1 and found[0] == (0, len(stripped))


def substitute_value(raw: Any, scope: Scope, where: str) -> Any:
    """Substitute inside a parameter value (recursing into lists and dicts).

    A string that is exactly one substitution is read back as a YAML scalar, so
    ``max_speed: $(arg speed)`` with ``speed:=0.5`` gives the float 0.5, as in ROS.
    """
    if isinstance(raw, str):
        text = substitute(raw, scope, where)
        if text != raw and _whole(raw):
            try:
                return yaml.safe_load(text) if text.strip() else text
            except yaml.YAMLError:
                return text
        return text
    if isinstance(raw, list):
        return [substitute_value(v, scope, f"{where}[{i}]") for i, v in enumerate(raw)]
    if isinstance(raw, dict):
        return {k: substitute_value(v, scope, f"{where}.{k}") for k, v in raw.items()}
    return raw


_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


def parse_bool(raw: Any, scope: Scope, where: str) -> bool:
    """A boolean field: YAML bool, or a string (after substitution) such as true/false/1/0.

    Raises:
        LaunchError: anything else.
    """
    if isinstance(raw, bool):
        return raw
    text = substitute(str(raw), scope, where).strip().lower() if isinstance(raw, (str, int)) else ""
    if text in _TRUE:
        return True
    if text in _FALSE:
        return False
    raise scope.fail(where, f"expected true or false, got {raw!r}")
