"""The optional compiled search (``_astar``), or None where it is not built.

``pip install`` compiles ``_astar.c`` when a C compiler is there; without one the planner
runs ``astar.search_python``, the reference the tests check the compiled code against.
Set ``ZENROS_NAV_PURE=1`` to use pure Python anyway.
"""

from __future__ import annotations

import importlib
import os
from types import ModuleType

__all__ = ["compiled"]


def _load() -> ModuleType | None:
    if os.environ.get("ZENROS_NAV_PURE", "") not in ("", "0"):
        return None
    try:
        return importlib.import_module(f"{__package__}._astar")
    except ImportError:
        return None


compiled = _load()
"""The compiled module, or None (not built, or ``ZENROS_NAV_PURE`` is set)."""
