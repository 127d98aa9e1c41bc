"""``png`` compression (``subscribe`` with ``compression: "png"``): a frame's JSON text packed
into a PNG image, sent as ``{"op": "png", "data": <the PNG, base64>}``, in the reference
server's layout, which roslibjs unpacks in the browser.

The layout: the UTF-8 text as the pixels of an 8-bit RGB image, three bytes a pixel, row
after row, ``floor(sqrt(n / 3))`` pixels wide (at least 1) and as many rows as the text
needs; the last row is padded with ``\\n`` (JSON whitespace, which a JSON parser skips).
"""

from __future__ import annotations

import base64
import io
import math

from PIL import Image

__all__ = ["png_frame", "png_text"]


def _pack(text: bytes) -> bytes:
    pixels = max(1, math.ceil(len(text) / 3))
    width = max(1, math.floor(math.sqrt(len(text) / 3)))
    height = math.ceil(pixels / width)
    padded = text + b"\n" * (width * height * 3 - len(text))
    out = io.BytesIO()
    Image.frombytes("RGB", (width, height), padded).save(out, "png")
    return out.getvalue()


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
