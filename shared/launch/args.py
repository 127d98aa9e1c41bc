"""Launch argument values checked against their declaration (``type``, ``choices``, ranges).

A value that does not fit stops the launch before anything starts, with one line that names
the argument as it is written on the command line (``speed:=abc: expected a number``).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from .model import ArgDecl

__all__ = ["check_value", "describe"]

_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


def check_value(decl: ArgDecl, value: str, cwd: Path | None = None) -> str:
    """The value of ``decl`` to use: ``value`` checked and normalized.

    Args:
        decl: the declaration.
        value: the text given (or the default, after substitution).
        cwd: the directory a relative ``file`` is read from (default: the working directory).

    Raises:
        ValueError: why it does not fit, without the argument's name.
    """
    text = value.strip()
    if decl.type == "bool":
        low = text.lower()
        if low not in _TRUE + _FALSE:
            raise ValueError(f"expected true or false, got {value!r}")
        text = "true" if low in _TRUE else "false"
    elif decl.type in ("int", "float"):
        text = _number(decl, text, value)
    elif decl.type == "file":
        text = _file(text, value, cwd)
    else:
        text = value
    if decl.choices and text not in decl.choices:
        raise ValueError(f"expected one of {', '.join(decl.choices)}, got {value!r}")
    return text


def _number(decl: ArgDecl, text: str, value: str) -> str:
    kind = "an integer" if decl.type == "int" else "a number"
    try:
        number = float(int(text)) if decl.type == "int" else float(text)
    except ValueError:
        number = math.nan
    if not math.isfinite(number):
        raise ValueError(f"expected {kind}{_range(decl)}, got {value!r}")
    if ((decl.min is not None and number < decl.min)
            or (decl.above is not None and number <= decl.above)
            or (decl.max is not None and number > decl.max)):
        raise ValueError(f"expected {kind}{_range(decl)}, got {value!r}")
    return text


def _range(decl: ArgDecl) -> str:
    parts = []
    if decl.min is not None:
        parts.append(f">= {decl.min:g}")
    if decl.above is not None:
        parts.append(f"> {decl.above:g}")
    if decl.max is not None:
        parts.append(f"<= {decl.max:g}")
    return (" " + " and ".join(parts)) if parts else ""


def _file(text: str, value: str, cwd: Path | None) -> str:
    if not text:
        raise ValueError("expected a file, got nothing")
    path = Path(os.path.expanduser(text))
    if not path.is_absolute():
        path = (cwd or Path.cwd()) / path
    if not path.exists():
        raise ValueError(f"no such file: {path}")
    if path.is_dir():
        raise ValueError(f"expected a file, got the directory {path}")
    return str(path)


def describe(decl: ArgDecl) -> str:
    """The type and limits of ``decl`` in words (for ``--show-args``), or ``""``."""
    if decl.choices:
        return "one of " + ", ".join(decl.choices)
    if decl.type == "str":
        return ""
    kind = {"bool": "true/false", "int": "integer", "float": "number", "file": "file"}[decl.type]
    return kind + _range(decl)
