"""Large WebSocket messages written a slice at a time, so the event loop keeps serving the
other connections: `SLICE`, `slices`.

A 5 MB message (a map as JSON) handed to an asyncio transport in one write is copied into
the kernel by one ``send`` call (most of it, on loopback), with the loop blocked meanwhile:
five clients, five such calls in a row, and every small message to every other client waits
for all of them. Sent as one fragmented WebSocket message (RFC 6455 section 5.4: a first frame and
continuation frames, which every client library reassembles), a slice per frame, with the
loop free between slices and each slice waiting for the socket to drain, no single write
holds the loop for more than a slice's copy. The message is the same message to the client.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from typing import Self

__all__ = ["SLICE", "SLICE_PAUSE", "Utf8Text", "paced_slices", "slices"]

SLICE = 256 * 1024
"""Bytes per frame of a message sent in slices (and the size above which one is)."""
SLICE_PAUSE = 0.004
"""Seconds between two slices of one message to one topic WebSocket connection: a 5 MB map
goes out over 80 ms rather than at once to every client, which on a 2-core machine left
/odom's p99 at 3x its figure without the map (1.2-1.4x paced); one connection's large
messages are capped at 64 MB/s."""


class Utf8Text(str):
    """A text frame that keeps its UTF-8 bytes: a server sending it to many clients
    (`SlicedWebSocketProtocol`) writes those instead of encoding the text again for each
    (5 ms per client of a 5 MB map, all of it holding the GIL). Still a plain ``str`` to
    everything else (ASGI takes text frames as ``str``)."""

    utf8: bytes

    def __new__(cls, data: bytes) -> Self:
        text = super().__new__(cls, data, "utf-8")
        text.utf8 = data
        return text


def slices(data: bytes, size: int = SLICE) -> list[memoryview]:
    """``data`` as consecutive views of ``size`` bytes (the last may be shorter; at least
    one, empty for empty data). Views, not copies: a 5 MB frame is not copied again."""
    view = memoryview(data)
    return [view[i:i + size] for i in range(0, len(data), size)] or [view]


async def paced_slices(data: bytes, size: int = SLICE) -> AsyncIterator[memoryview]:
    """`slices` for ``websockets``' ``send`` (a fragmented message), the loop running its
    other tasks between slices (``send`` itself waits for the socket to drain)."""
    for i, part in enumerate(slices(data, size)):
        if i:
            await asyncio.sleep(0)
        yield part
