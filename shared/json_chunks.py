"""JSON of large messages without holding up every other thread: `BulkEncoder`.

Encoding a 2 MB OccupancyGrid as JSON takes 100-160 ms in one C call (msgspec), and a C call
keeps the GIL throughout: every other Python thread (Zenoh's receive thread, an event loop
sending small messages) stops for that long. `json_chunks` encodes a message's big arrays
slice by slice (`CHUNK` elements, a few ms each) and `encode_yielding` rests between slices
(`PACE`), giving the GIL away and leaving most of a core to the small messages; `BulkEncoder`
runs that on a worker thread of its own, so the thread that received the message returns at
once. The bytes are exactly `zenros.codec.json_bytes`'s.
"""

from __future__ import annotations

import base64
import concurrent.futures
import itertools
import time
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import msgspec
import numpy as np

from .codec import json_bytes
from .message import UInt8Array

__all__ = ["BULK_ELEMENTS", "CHUNK", "PACE", "BulkEncoder", "encode_yielding", "is_bulky",
           "json_chunks", "paced"]

T = TypeVar("T")

CHUNK = 8192
"""Array elements encoded in one C call (well under 1 ms on a quiet machine of this class)."""
BULK_ELEMENTS = 65536
"""A message with an array at least this long is encoded off the receiving thread."""
PACE = 2.0
"""`encode_yielding` rests this many times as long as each piece took: the encoding of a
large message takes at most a third of a core."""


def _fields(obj: msgspec.Struct) -> tuple[str, ...]:
    return obj.__struct_fields__


def is_bulky(obj: Any, threshold: int = BULK_ELEMENTS) -> bool:
    """Whether ``obj`` (a message) holds a numpy array of at least ``threshold`` elements."""
    if isinstance(obj, np.ndarray):
        return obj.size >= threshold
    if isinstance(obj, msgspec.Struct):
        return any(is_bulky(getattr(obj, f), threshold) for f in _fields(obj))
    return False


def json_chunks(obj: Any, threshold: int = CHUNK) -> Iterator[bytes]:
    """``json_bytes(obj)`` in pieces: each 1-D array longer than ``threshold`` ``CHUNK``
    elements at a time, everything else in one piece per field."""
    if isinstance(obj, UInt8Array) and obj.size > threshold:  # base64, 3 bytes to 4 chars
        step = 3 * CHUNK * 8
        yield b'"'
        for start in range(0, obj.size, step):
            yield base64.b64encode(np.ascontiguousarray(obj[start:start + step]).data)
        yield b'"'
    elif isinstance(obj, np.ndarray) and obj.ndim == 1 and obj.size > threshold:
        yield b"["
        for start in range(0, obj.size, CHUNK):
            if start:
                yield b","
            yield json_bytes(obj[start:start + CHUNK])[1:-1]
        yield b"]"
    elif isinstance(obj, msgspec.Struct) and is_bulky(obj, threshold + 1):
        config = obj.__struct_config__
        names = obj.__struct_encode_fields__
        first = True
        yield b"{"
        if config.tag_field is not None:
            yield json_bytes(config.tag_field) + b":" + json_bytes(config.tag)
            first = False
        for name, key in zip(_fields(obj), names, strict=True):
            yield (b"" if first else b",") + json_bytes(key) + b":"
            first = False
            yield from json_chunks(getattr(obj, name), threshold)
        yield b"}"
    else:
        yield json_bytes(obj)


def encode_yielding(obj: Any, rest: float = PACE, head: bytes = b"", tail: bytes = b"") -> bytes:
    """``json_bytes(obj)``, resting ``rest`` times as long as each piece took before the next.

    The rest releases the GIL, so a waiting thread runs now, not after the whole map, and it
    paces the encoding: at the default (`PACE`), a 2 MB map's 20-30 ms of encoding is spread
    over three times as long and takes at most a third of a core meanwhile, which leaves
    the rest to the small messages that arrive during it (docs/rosbridge.md, "Large
    messages"). ``rest=0`` only gives the GIL away.

    ``head`` and ``tail`` go around the JSON in the same join (a rosbridge ``publish``
    frame): each copy of a 5 MB result holds the GIL for 2-3 ms (its fresh pages are
    faulted in as it is written), and at the end of a map's encoding the gateway's other
    threads stalled 6-9 ms on the three copies a join and a concatenation made."""
    return b"".join(itertools.chain((head,), paced(json_chunks(obj), rest), (tail,)))


def paced(pieces: Iterator[T], rest: float = PACE) -> Iterator[T]:
    """The items of ``pieces``, resting ``rest`` times as long as each took to make (with
    the GIL given away) before asking for the next."""
    clock = time.perf_counter
    t0 = clock()
    for piece in pieces:  # a piece is made here
        yield piece
        time.sleep(rest * (clock() - t0))
        t0 = clock()


class BulkEncoder:
    """One worker thread that encodes large messages in order (`encode_yielding`).

    Args:
        name: the worker thread's name (seen in ``py-spy``/``top -H``).
    """

    def __init__(self, name: str = "json-bulk") -> None:
        self._pool = concurrent.futures.ThreadPoolExecutor(max_workers=1,
                                                           thread_name_prefix=name)

    def submit(self, work: Callable[[], Any]) -> concurrent.futures.Future[Any] | None:
        """Run ``work`` on the worker, after everything submitted before it (None, and not
        run, once closed: a late message at shutdown)."""
        try:
            return self._pool.submit(work)
        except RuntimeError:  # closed
            return None

    def close(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)
