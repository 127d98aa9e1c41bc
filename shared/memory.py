"""`keep_freed_buffers`: glibc's malloc keeps freed large buffers for the next ones.

A process that handles a large message every second (the gateway: a 2 MB map becomes a 5 MB
JSON frame and a 2 MB CBOR one, each copied once or twice) gets, by default, each such buffer
from a fresh ``mmap`` and gives it back on free: every copy into it then faults its pages in,
one by one, and holds the GIL meanwhile (2-3 ms for 5 MB on our 2-core box, against 0.2 ms
into pages already mapped), and the small messages of every other thread wait. With the
thresholds raised, buffers up to 32 MiB come from the heap and freed memory stays mapped for
the next message (at most 64 MiB of it).
"""

from __future__ import annotations

import ctypes
import sys

__all__ = ["MMAP_THRESHOLD", "TRIM_THRESHOLD", "keep_freed_buffers"]

MMAP_THRESHOLD = 32 << 20  # bytes: larger allocations still get their own mapping
TRIM_THRESHOLD = 64 << 20  # bytes of free heap kept mapped before giving any back
_M_TRIM_THRESHOLD = -1  # glibc <malloc.h>
_M_MMAP_THRESHOLD = -3


def keep_freed_buffers(mmap_threshold: int = MMAP_THRESHOLD,
                       trim_threshold: int = TRIM_THRESHOLD) -> bool:
    """Set glibc's ``M_MMAP_THRESHOLD`` and ``M_TRIM_THRESHOLD`` for this process; False
    (and nothing changed) where there is no glibc ``mallopt`` (macOS, Windows, musl)."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    mallopt.restype = ctypes.c_int
    return bool(mallopt(_M_MMAP_THRESHOLD, mmap_threshold)) and bool(
        mallopt(_M_TRIM_THRESHOLD, trim_threshold))
