"""``png`` compression (``subscribe`` with ``compression: "png"``): a frame's JSON text packed
into a PNG image, sent as ``{"op": "png", "data": <the PNG, base64>}``, in the reference
server's layout, which roslibjs unpacks in the browser.

The layout: the UTF-8 text as the pixels of an 8-bit RGB image, three bytes a pixel, row
after row, ``floor(sqrt(n / 3))`` pixels wide (at least 1) and as many rows as the text
needs; the last row is padded with ``\\n`` (JSON whitespace, which a JSON parser skips).

The image is written here (a PNG is a signature and three chunks), not by Pillow: rows
unfiltered and deflated at level 3 (`LEVEL`), a 2 MB map's 4.6 MB of JSON takes 27 ms and
226 KB where Pillow's adaptive filters at level 6 took 151 ms and 190 KB, CPU that the
gateway's other clients wait for on a small box (docs/rosbridge.md, "Large messages").
Pillow still reads them (`png_text`), as a browser does.
"""

from __future__ import annotations

import base64
import io
import math
import struct
import zlib
from collections.abc import Iterator

from PIL import Image
from zenros.json_chunks import paced

__all__ = ["LEVEL", "png_frame", "png_text"]

DEFLATE_SLICE = 256 * 1024
"""Bytes deflated in one call (about 1.5 ms at `LEVEL`)."""
LEVEL = 3  # zlib's: 1-2 are a few ms faster and 15-25 % larger, 6 three times slower
_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_RGB8 = (8, 2, 0, 0, 0)  # bit depth 8, colour type 2 (RGB), deflate, filters of type 0, no interlace


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def _pack(text: bytes) -> bytes:
    pixels = max(1, math.ceil(len(text) / 3))
    width = max(1, math.floor(math.sqrt(len(text) / 3)))
    height = math.ceil(pixels / width)
    row = width * 3
    padded = text + b"\n" * (row * height - len(text))
    # each row: its filter type (0, none), then its pixels
    rows = b"".join(b"\x00" + padded[i:i + row] for i in range(0, len(padded), row))
    return (_SIGNATURE + _chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, *_RGB8))
            + _chunk(b"IDAT", _deflate(rows)) + _chunk(b"IEND", b""))


def _deflate(data: bytes) -> bytes:
    """``zlib.compress(data, LEVEL)``'s stream, a `DEFLATE_SLICE` at a time and paced
    (`zenros.json_chunks.paced`): a map's 27 ms of deflating is spread out rather than
    taken from the other clients at once (zlib gives the GIL up as it works, the CPU not)."""
    z = zlib.compressobj(LEVEL)
    view = memoryview(data)

    def pieces() -> Iterator[bytes]:
        for i in range(0, len(data), DEFLATE_SLICE):
            yield z.compress(view[i:i + DEFLATE_SLICE])
        yield z.flush()

    return b"".join(paced(pieces()))


def png_frame(frame: bytes) -> bytes:
    """The ``png`` frame carrying ``frame`` (a JSON text frame, UTF-8)."""
    data = base64.b64encode(_pack(frame))
    return b'{"op":"png","data":"' + data + b'"}'


def png_text(data: str) -> bytes:
    """The JSON text in a ``png`` frame's ``data`` (its padding removed), as a client
    unpacks it.

    Raises:
        ValueError: ``data`` is not base64 of an RGB PNG.
    """
    with Image.open(io.BytesIO(base64.b64decode(data, validate=True)), formats=("png",)) as img:
        return img.convert("RGB").tobytes().rstrip(b"\n")
