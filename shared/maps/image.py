"""Map image files: 8-bit PGM (P5/P2) with numpy, PNG and other formats through Pillow.

Images are (rows, cols) uint8 grey arrays, or (rows, cols, 2|4) with an alpha channel,
top row first, as in the file.
"""

from __future__ import annotations

import io
import re
from pathlib import Path

import numpy as np

from ..errors import MapError

__all__ = ["encode_image", "read_image", "write_image"]

_PGM_HEADER = re.compile(rb"^(P[25])(?:\s+|#[^\n]*\n)*")
_TOKEN = re.compile(rb"(?:\s|#[^\n]*\n)*(\d+)")


def _read_pgm(data: bytes, where: str) -> np.ndarray:
    head = _PGM_HEADER.match(data)
    if head is None:
        raise MapError(f"{where}: not a PGM image (expected a P5 or P2 header)")
    pos = head.start(1) + 2
    values: list[int] = []
    for _ in range(3):
        m = _TOKEN.match(data, pos)
        if m is None:
            raise MapError(f"{where}: truncated PGM header (width, height, maxval)")
        values.append(int(m.group(1)))
        pos = m.end()
    width, height, maxval = values
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise MapError(f"{where}: bad PGM size {width}x{height} or maxval {maxval}")
    n = width * height
    if head.group(1) == b"P5":
        dtype = np.dtype(">u2") if maxval > 255 else np.dtype(np.uint8)
        body = data[pos + 1: pos + 1 + n * dtype.itemsize]
        if len(body) != n * dtype.itemsize:
            raise MapError(f"{where}: PGM has {len(body)} bytes of pixels, expected "
                           f"{n * dtype.itemsize} for {width}x{height}")
        pixels = np.frombuffer(body, dtype=dtype).astype(np.float64)
    else:
        pixels = np.array(data[pos:].split(), dtype=np.float64)
        if pixels.size != n:
            raise MapError(f"{where}: PGM has {pixels.size} pixels, expected {n}")
    if maxval != 255:
        pixels = np.round(pixels * (255.0 / maxval))
    return pixels.astype(np.uint8).reshape(height, width)


def read_image(path: str | Path) -> np.ndarray:
    """Read a map image; PGM directly, anything else (PNG, BMP, ...) through Pillow.

    Raises:
        MapError: missing or unreadable file, or an unsupported image.
    """
    path = Path(path)
    where = str(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MapError(f"{where}: cannot read map image: {exc.strerror or exc}") from exc
    if data[:2] in (b"P5", b"P2"):
        return _read_pgm(data, where)
    try:
        from PIL import Image, UnidentifiedImageError
    except ImportError as exc:  # pragma: no cover - Pillow is a dependency
        raise MapError(f"{where}: reading this image needs Pillow") from exc
    try:
        with Image.open(io.BytesIO(data)) as img:
            img.load()
            conv: Image.Image
            if img.mode in ("L", "LA", "RGB", "RGBA"):
                conv = img
            elif "A" in img.getbands() or "transparency" in img.info:
                conv = img.convert("RGBA")
            elif img.mode in ("I", "I;16", "F"):
                arr = np.asarray(img, dtype=np.float64)
                hi = 65535.0 if arr.max(initial=0) > 255 else 255.0
                return np.round(arr * (255.0 / hi)).astype(np.uint8)
            else:
                conv = img.convert("RGB")
            return np.asarray(conv, dtype=np.uint8).copy()
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise MapError(f"{where}: not a readable image: {exc}") from exc


def encode_image(pixels: np.ndarray, fmt: str) -> bytes:
    """Encode grey (rows, cols) or grey+alpha (rows, cols, 2) uint8 pixels as ``pgm`` or ``png``."""
    if fmt == "pgm":
        if pixels.ndim != 2:
            raise MapError("PGM cannot hold an alpha channel; use png")
        h, w = pixels.shape
        return b"P5\n%d %d\n255\n" % (w, h) + np.ascontiguousarray(pixels, np.uint8).tobytes()
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(pixels, np.uint8)).save(buf, format=fmt.upper())
    return buf.getvalue()


def write_image(pixels: np.ndarray, path: str | Path) -> None:
    """Write pixels to ``path``, the format taken from its suffix (``.pgm`` or ``.png``)."""
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in ("pgm", "png"):
        raise MapError(f"{path}: unsupported image format {fmt!r}; use .pgm or .png")
    path.write_bytes(encode_image(pixels, fmt))
