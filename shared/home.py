"""The data dir: ``$ZENROS_HOME``, else ``~/.zenros`` (databases, maps, bags, logs)."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["data_dir"]


def data_dir(configured: str = "") -> Path:
    """``configured`` if given, else ``$ZENROS_HOME``, else ``~/.zenros``."""
    return Path(configured or os.environ.get("ZENROS_HOME") or Path.home() / ".zenros").expanduser()
