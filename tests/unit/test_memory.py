"""`keep_freed_buffers`: glibc's malloc thresholds raised, so a large buffer freed is reused
by the next one instead of being unmapped (its pages stay faulted in)."""

from __future__ import annotations

import ctypes
import platform
import sys

import pytest
from zenros.memory import keep_freed_buffers

glibc = sys.platform.startswith("linux") and platform.libc_ver()[0] == "glibc"


@pytest.mark.skipif(not glibc, reason="mallopt is glibc's")
def test_large_buffers_come_from_the_heap_and_stay_mapped() -> None:
    assert keep_freed_buffers() is True
    assert keep_freed_buffers() is True  # idempotent

    class Mallinfo2(ctypes.Structure):
        _fields_ = [(name, ctypes.c_size_t) for name in (
            "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks",
            "uordblks", "fordblks", "keepcost")]

    mallinfo2 = ctypes.CDLL(None).mallinfo2
    mallinfo2.restype = Mallinfo2
    before = mallinfo2()
    big = bytes(8 << 20)  # 8 MiB: a mapping of its own by default (over 128 KiB)
    during = mallinfo2()
    assert during.hblks == before.hblks  # not a separate mmap: from the heap
    del big
    after = mallinfo2()
    assert after.arena >= during.arena - (1 << 20)  # freed, but still mapped for the next one


@pytest.mark.skipif(glibc, reason="only where there is no glibc")
def test_without_glibc_nothing_changes() -> None:
    assert keep_freed_buffers() is False
