"""The optional C hot paths of the buffer (``_speedups``), or None where it is not built.

``pip install`` compiles ``_speedups.c`` when a C compiler is there; without one the
build skips it and the buffer runs the same algorithms in Python. The Python code is the
reference: tests run both. Set ``ZENROS_TF_PURE=1`` to use pure Python anyway.
"""

from __future__ import annotations

import os
from types import ModuleType

from ..msgs.builtin_interfaces import Time
from ..msgs.geometry_msgs import Quaternion, Transform, TransformStamped, Vector3
from ..msgs.std_msgs import Header
from .cache import COMPACT_AT, TimeCache

__all__ = ["speedups"]


def _load() -> ModuleType | None:
    if os.environ.get("ZENROS_TF_PURE", "") not in ("", "0"):
        return None
    try:
        from . import _speedups
    except ImportError:
        return None
    if _speedups.COMPACT_AT != COMPACT_AT:  # a stale build next to newer Python code
        return None
    _speedups.bind(TransformStamped, Header, Time, Transform, Vector3, Quaternion, TimeCache)
    return _speedups


speedups = _load()
"""The compiled module, or None (not built, or ``ZENROS_TF_PURE`` is set)."""
