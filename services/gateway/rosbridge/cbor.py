"""CBOR topic frames (``subscribe`` with ``compression: "cbor"`` or ``"cbor-raw"``), in the
reference server's format, sent as binary WebSocket frames.

* ``cbor``: the ``publish`` frame as CBOR, its ``msg`` with the ROS field layout: numeric
  arrays as RFC 8746 typed arrays (little endian: tag 69 uint16, 70 uint32, 71 uint64,
  72 int8, 77 int16, 78 int32, 79 int64, 85 float32, 86 float64), ``uint8``/``char``/``byte``
  arrays as a byte string, bool and string arrays as arrays, times as ``sec``/``nanosec``.
  The widths come from the type's ROS 2 definition (zenros.ros2). Fixed-size arrays
  (``float64[9]`` covariances) are typed arrays too.
* ``cbor-raw``: ``msg`` is ``{"secs", "nsecs", "bytes"}``: the time the bridge sends it and
  the message's ROS 2 CDR serialization (what the reference's ROS 2 server hands its clients).

A topic of a type zenros does not know (opaque.py) is sent as the CBOR of its JSON.
"""

from __future__ import annotations

from typing import Any

import cbor2
import numpy as np
from zenros.message import Message
from zenros.msgs.builtin_interfaces import Time
from zenros.ros2 import cdr_codec, definition, ros_name_of
from zenros.ros2.idl import MsgDef

__all__ = ["cbor_frame", "cbor_frame_from_json", "cbor_raw_frame", "cbor_values", "is_binary"]

TAGS: dict[str, tuple[int, str]] = {
    "uint16": (69, "<u2"),
    "uint32": (70, "<u4"),
    "uint64": (71, "<u8"),
    "int8": (72, "i1"),
    "int16": (77, "<i2"),
    "int32": (78, "<i4"),
    "int64": (79, "<i8"),
    "float32": (85, "<f4"),
    "float64": (86, "<f8"),
}
BYTES = ("uint8", "char", "byte")


def is_binary(frame: bytes | str) -> bool:
    """Whether ``frame`` goes out as a binary WebSocket message: a CBOR frame (a map, first
    byte 0xa0-0xbf), not JSON text (every text frame of the protocol is a JSON object, ``{``).
    Told by its first byte, so a 2 MB CBOR frame is not copied into a marker type."""
    return isinstance(frame, bytes) and frame[:1] != b"{"


_DEFINITIONS: dict[type, MsgDef] = {}


def _definition(cls: type) -> MsgDef:
    d = _DEFINITIONS.get(cls)
    if d is None:
        d = _DEFINITIONS[cls] = definition(ros_name_of(cls))
    return d


def cbor_values(msg: Message) -> dict[str, Any]:
    """``msg`` as CBOR-ready values (typed arrays as `cbor2.CBORTag`)."""
    out: dict[str, Any] = {}
    for f in _definition(type(msg)).fields:
        value = getattr(msg, f.name)
        t = f.type
        if t.kind == "single":
            if isinstance(value, Message):
                out[f.name] = cbor_values(value)
            elif isinstance(value, np.generic):
                out[f.name] = value.item()
            else:
                out[f.name] = value
        elif t.base in BYTES:
            out[f.name] = value if isinstance(value, bytes) else \
                np.asarray(value, dtype=np.uint8).tobytes()
        elif t.base in TAGS:
            tag, dtype = TAGS[t.base]
            out[f.name] = cbor2.CBORTag(tag, np.asarray(value, dtype=dtype).tobytes())
        elif t.base == "bool":
            out[f.name] = [bool(v) for v in value]
        elif t.base in ("string", "wstring"):
            out[f.name] = [str(v) for v in value]
        else:
            out[f.name] = [cbor_values(v) for v in value]
    return out


def cbor_frame(topic: str, msg: Message) -> bytes:
    """The ``cbor`` publish frame of ``msg``."""
    frame: bytes = cbor2.dumps({"op": "publish", "topic": topic, "msg": cbor_values(msg)})
    return frame


def cbor_raw_frame(topic: str, msg: Message, now: Time) -> bytes:
    """The ``cbor-raw`` publish frame of ``msg``: its CDR bytes and the time ``now``."""
    raw = cdr_codec(type(msg)).encode(msg)
    frame: bytes = cbor2.dumps({"op": "publish", "topic": topic, "msg": {
        "secs": now.sec, "nsecs": now.nanosec, "bytes": raw}})
    return frame


def cbor_frame_from_json(obj: Any) -> bytes:
    """A frame already in JSON (a topic of a type zenros has no definition for) as CBOR."""
    frame: bytes = cbor2.dumps(obj)
    return frame
