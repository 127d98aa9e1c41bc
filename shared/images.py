"""`sensor_msgs/Image` as numpy, both ways (what cv_bridge and ros2_numpy give a ROS user,
without OpenCV): `image_to_numpy` is a zero-copy view of the message's bytes, shaped
(height, width) or (height, width, channels), row padding (``step``) and byte order honoured;
`numpy_to_image` makes the message of an array. Encodings are ROS's
(``sensor_msgs/image_encodings``): rgb8, bgr8, rgba8, bgra8, mono8, mono16, the bayer ones,
yuv422 and ``{8,16,32,64}{U,S,F}C{1..4}``."""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from .errors import DecodeError, EncodeError
from .message import UInt8Array, to_array
from .msgs.sensor_msgs import Image
from .msgs.std_msgs import Header

__all__ = ["encoding_layout", "image_to_numpy", "numpy_to_image"]

_NAMED: dict[str, tuple[str, int]] = {
    "rgb8": ("u1", 3), "bgr8": ("u1", 3), "rgba8": ("u1", 4), "bgra8": ("u1", 4),
    "mono8": ("u1", 1), "mono16": ("u2", 1), "rgb16": ("u2", 3), "bgr16": ("u2", 3),
    "rgba16": ("u2", 4), "bgra16": ("u2", 4), "yuv422": ("u1", 2), "uyvy": ("u1", 2),
    "yuyv": ("u1", 2), "yuv422_yuy2": ("u1", 2),
}
_CV = re.compile(r"^(8|16|32|64)(U|S|F)C([1-4])$")
_BAYER = re.compile(r"^bayer_(rggb|bggr|gbrg|grbg)(8|16)$")


def encoding_layout(encoding: str) -> tuple[np.dtype[Any], int]:
    """The element type (little-endian) and channel count of a ROS image encoding."""
    name = encoding.strip()
    if name in _NAMED:
        code, channels = _NAMED[name]
        return np.dtype("<" + code), channels
    m = _CV.match(name.upper())
    if m:
        bits, kind, channels = int(m.group(1)), m.group(2), int(m.group(3))
        if kind == "F" and bits < 32:
            raise ValueError(f"image encoding {encoding!r}: floats are 32 or 64 bits")
        code = {"U": "u", "S": "i", "F": "f"}[kind] + str(bits // 8)
        return np.dtype("<" + code), channels
    m = _BAYER.match(name)
    if m:
        return np.dtype("<u1" if m.group(2) == "8" else "<u2"), 1
    raise ValueError(f"unknown image encoding {encoding!r} (rgb8, bgr8, mono8, mono16, "
                     "32FC1, ... as sensor_msgs/image_encodings names them)")


def image_to_numpy(msg: Image) -> np.ndarray[Any, Any]:
    """The pixels of ``msg`` as an array viewing its bytes (read-only; ``.copy()`` to edit).

    Raises:
        DecodeError: an unknown encoding, or fewer bytes than height x step.
    """
    try:
        dtype, channels = encoding_layout(msg.encoding)
    except ValueError as exc:
        raise DecodeError(str(exc)) from None
    if msg.is_bigendian:
        dtype = dtype.newbyteorder(">")
    row = msg.width * channels * dtype.itemsize
    step = msg.step or row
    if step < row:
        raise DecodeError(f"image step {step} is less than a row ({msg.width} x {channels} x "
                          f"{dtype.itemsize} bytes)")
    need = step * msg.height
    if len(msg.data) < need:
        raise DecodeError(f"image data has {len(msg.data)} bytes; {msg.height} rows of "
                          f"{step} need {need}")
    rows = np.frombuffer(msg.data, np.uint8, need).reshape(msg.height, step)[:, :row]
    pixels = rows.view(dtype) if step == row else np.ascontiguousarray(rows).view(dtype)
    shape = (msg.height, msg.width) if channels == 1 else (msg.height, msg.width, channels)
    return pixels.reshape(shape)


def numpy_to_image(array: np.ndarray[Any, Any], encoding: str,
                   header: Header | None = None) -> Image:
    """An Image of ``array`` (height x width, or height x width x channels) in ``encoding``.

    Raises:
        EncodeError: the array's shape or element type does not fit the encoding.
    """
    try:
        dtype, channels = encoding_layout(encoding)
    except ValueError as exc:
        raise EncodeError(str(exc)) from None
    arr = np.asarray(array)
    if arr.ndim == 2:
        arr = arr[:, :, None]
    if arr.ndim != 3 or arr.shape[2] != channels:
        raise EncodeError(f"encoding {encoding} takes (height, width"
                          f"{'' if channels == 1 else f', {channels}'}) arrays, got "
                          f"shape {np.shape(array)}")
    if arr.dtype.kind != dtype.kind or arr.dtype.itemsize != dtype.itemsize:
        raise EncodeError(f"encoding {encoding} holds {dtype.name}, the array is {arr.dtype}")
    little = np.ascontiguousarray(arr, dtype=dtype)
    height, width = little.shape[:2]
    data = to_array(UInt8Array, little.tobytes())  # one copy: the message owns its pixels
    return Image(header=header if header is not None else Header(), height=height,
                 width=width, encoding=encoding, is_bigendian=0,
                 step=width * channels * dtype.itemsize, data=data)
