"""`Encodings`: one topic message as the frames clients ask for, each made once, on demand.

A client subscribes with a ``compression`` (none, ``png``, ``cbor``, ``cbor-raw``); every
client gets its own format of the same message, and each format is encoded once for all of
them. A large message (`zenros.json_chunks.is_bulky`) is encoded on the bridge's worker
thread before it reaches the loop (bridge.py), so a 5 MB JSON text never stalls the loop.
"""

from __future__ import annotations

import json
import threading
from collections.abc import Callable
from typing import Any

from zenros.json_chunks import encode_yielding
from zenros.message import Message
from zenros.msgs.builtin_interfaces import Time

from .cbor import cbor_frame, cbor_frame_from_json, cbor_raw_frame
from .convert import encode_message, publish_frame, publish_frame_ends
from .png import png_frame

__all__ = ["FORMATS", "Encodings"]

FORMATS = ("json", "png", "cbor", "cbor-raw")
"""What `Encodings` makes: JSON text frames, ``png`` frames (png.py) and the binary CBOR
ones (cbor.py)."""


class Encodings:
    """The frames of one message on one topic.

    Args:
        topic: the topic the frames name.
        msg: the message (a registered type), or None for ``json_frame``.
        json_frame: the ``publish`` frame already made (a topic of an unchecked type).
        now: the bridge's clock, for ``cbor-raw``'s time.
        bulky: encode JSON a slice at a time (`encode_yielding`), for messages that take
            longer than a few milliseconds.
    """

    def __init__(self, topic: str, msg: Message | None = None, json_frame: bytes | None = None,
                 now: Callable[[], Time] | None = None, bulky: bool = False) -> None:
        self.topic = topic
        self.msg = msg
        self._now = now
        self._bulky = bulky
        self._done: dict[str, bytes] = {}
        self._lock = threading.RLock()
        if json_frame is not None:
            self._done["json"] = json_frame

    def __call__(self, fmt: str) -> bytes:
        """The frame in ``fmt`` (one of `FORMATS`).

        Raises:
            ValueError, TypeError: the message cannot be put in that format.
        """
        with self._lock:
            frame = self._done.get(fmt)
            if frame is None:
                frame = self._done[fmt] = self._make(fmt)
            return frame

    def _make(self, fmt: str) -> bytes:
        msg = self.msg
        if fmt == "json":
            assert msg is not None
            if self._bulky:  # the frame made in one join (`encode_yielding`)
                head, tail = publish_frame_ends(self.topic)
                return encode_yielding(msg, head=head, tail=tail)
            return publish_frame(self.topic, encode_message(msg))
        if fmt == "png":
            return png_frame(self("json"))
        if msg is None:
            obj: Any = json.loads(self("json"))
            if fmt in ("cbor", "cbor-raw"):
                return cbor_frame_from_json(obj)
        elif fmt == "cbor":
            return cbor_frame(self.topic, msg)
        elif fmt == "cbor-raw":
            assert self._now is not None
            return cbor_raw_frame(self.topic, msg, self._now())
        raise ValueError(f"unknown format {fmt!r}")
