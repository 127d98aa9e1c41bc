"""A msgspec Struct kept in a JSON file: read once at start, written atomically on change."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import TypeVar

import msgspec
from zenros.errors import ConfigError

__all__ = ["load_struct", "save_struct"]

T = TypeVar("T", bound=msgspec.Struct)


def load_struct(path: Path | None, kind: type[T]) -> T:
    """The struct stored in ``path``, or ``kind()`` when there is no file.

    Raises:
        ConfigError: the file is not a valid ``kind`` (the message names the file).
    """
    if path is None or not path.exists():
        return kind()
    try:
        return msgspec.json.decode(path.read_bytes(), type=kind)
    except msgspec.MsgspecError as exc:
        raise ConfigError(f"{path}: {exc}") from exc


def save_struct(path: Path | None, value: msgspec.Struct) -> None:
    """Write ``value`` to ``path`` (a temporary file renamed over it); None: nothing."""
    if path is None:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(msgspec.to_builtins(value), indent=1, ensure_ascii=False),
                   encoding="utf-8")
    os.replace(tmp, path)
