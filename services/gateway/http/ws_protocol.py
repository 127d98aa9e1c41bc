"""`SlicedWebSocketProtocol`: uvicorn's WebSocket protocol, with messages over `SLICE` bytes
sent as a fragmented message a slice at a time (ws_slices.py) instead of in one write.

uvicorn writes a message as one ``transport.write`` of the whole frame, after two more
copies of it (the text encoded, the frame serialized, the pieces joined): for a 5 MB map to
five clients that kept the gateway's loop, which serves every other WebSocket and the REST
API, for 25-30 ms per map. Here a large message goes out as frames of `SLICE` bytes,
each written once the socket has taken the previous ones (the transport's flow control) and
`SLICE_PAUSE` after the previous one, the loop serving the other connections between slices.
Sends on one connection are serialized (a lock), so no data frame ever lands inside another
message's fragments; control frames (pings) may, as RFC 6455 allows.
"""

from __future__ import annotations

import asyncio
from typing import Any

from uvicorn.protocols.utils import ClientDisconnected
from uvicorn.protocols.websockets.websockets_sansio_impl import WebSocketsSansIOProtocol
from websockets.exceptions import InvalidState

from ..ws_slices import SLICE, SLICE_PAUSE, Utf8Text, slices

__all__ = ["SlicedWebSocketProtocol"]


class SlicedWebSocketProtocol(WebSocketsSansIOProtocol):
    """Pass as ``uvicorn.Config(ws=SlicedWebSocketProtocol)``."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._send_lock = asyncio.Lock()

    async def send(self, message: Any) -> None:
        if message["type"] != "websocket.send":
            async with self._send_lock:
                await super().send(message)
            return
        text = message.get("text")
        data = message.get("bytes")
        size = len(text) if text is not None else len(data) if data is not None else 0
        async with self._send_lock:
            if size <= SLICE or not self.handshake_complete or self.close_sent:
                await super().send(message)
                return
            if text is not None:  # encoded once for every client (the topic hub's frames)
                data = text.utf8 if isinstance(text, Utf8Text) else text.encode()
            await self._send_sliced(data, binary=text is None)

    async def _send_sliced(self, payload: bytes, binary: bool) -> None:
        parts = slices(payload)
        for i, part in enumerate(parts):
            await self.writable.wait()  # the socket took what was written before
            if self.disconnected or self.transport.is_closing():
                raise ClientDisconnected()
            fin = i == len(parts) - 1
            try:
                if i:
                    self.conn.send_continuation(part, fin=fin)
                elif binary:
                    self.conn.send_binary(part, fin=fin)
                else:
                    self.conn.send_text(part, fin=fin)
            except InvalidState:
                raise ClientDisconnected() from None
            self.transport.write(b"".join(self.conn.data_to_send()))
            if not fin:
                # the other connections' frames go out in between, and the large one
                # is paced (ws_slices.SLICE_PAUSE)
                await asyncio.sleep(SLICE_PAUSE)
