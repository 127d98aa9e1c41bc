"""The optional compiled distance transform (``_edt``), or None where it is not built.

``pip install`` compiles ``_edt.c`` when a C compiler is there; without one the inflation
layer runs ``inflation.squared_distance`` in numpy, the reference the tests check the
compiled code against. Set ``ZENROS_NAV_PURE=1`` to use numpy anyway.
"""

from __future__ import annotations

import importlib
import os
from types import ModuleType

__all__ = ["edt"]


def _load() -> ModuleType | None:
    if os.environ.get("ZENROS_NAV_PURE", "") not in ("", "0"):
        return None
    try:
        return importlib.import_module(f"{__package__}._edt")
    except ImportError:
        return None


edt = _load()
"""The compiled module, or None (not built, or ``ZENROS_NAV_PURE`` is set)."""
