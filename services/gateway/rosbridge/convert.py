"""JSON ↔ zenros messages for rosbridge: ROS field layouts as they are, type names, frames."""

from __future__ import annotations

import base64
import binascii
from typing import Any

import msgspec
from zenros.codec import from_builtins, json_bytes, to_builtins
from zenros.message import Message, UInt8Array, normalize_type_name
from zenros.msgs.builtin_interfaces import Time

__all__ = [
    "dumps",
    "encode_message",
    "long_type",
    "message_from_json",
    "publish_frame",
    "request_args",
    "to_json",
]


def dumps(obj: Any) -> bytes:
    """One frame as UTF-8 JSON (NaN and infinities become ``null``, as rosbridge writes them)."""
    return json_bytes(obj)


def encode_message(msg: Message) -> bytes:
    """A message as the JSON object rosbridge sends (the ROS field layout)."""
    return json_bytes(msg)


def to_json(msg: Message) -> Any:
    """A message as plain dicts and lists."""
    return to_builtins(msg)


def publish_frame(topic: str, msg_json: bytes) -> bytes:
    """``{"op":"publish","topic":...,"msg":...}`` around an encoded message, without re-parsing."""
    head, tail = publish_frame_ends(topic)
    return head + msg_json + tail


def publish_frame_ends(topic: str) -> tuple[bytes, bytes]:
    """What goes before and after the message in `publish_frame`."""
    return b'{"op":"publish","topic":' + dumps(topic) + b',"msg":', b"}"


def long_type(name: str, kind: str = "msg") -> str:
    """``std_msgs/String`` as ROS 2 rosapi reports it: ``std_msgs/msg/String``."""
    parts = normalize_type_name(name).split("/")
    if len(parts) == 2:
        return f"{parts[0]}/{kind}/{parts[1]}"
    return name


def _fields(msg_type: type[Message]) -> dict[str, Any]:
    return {f.name: f.type for f in msgspec.structs.fields(msg_type)}


def message_from_json(obj: Any, msg_type: type[Message], now: Time | None = None) -> Message:
    """Build ``msg_type`` from a rosbridge JSON object.

    Missing fields take their defaults; an unknown field is an error (as rosbridge's
    ``NonexistentFieldException``); a missing ``header.stamp`` is set to ``now``; a ``uint8[]``
    field may come as a base64 string.

    Raises:
        DecodeError: the object does not fit the type (the message names the path).
        TypeError: ``obj`` is not a JSON object.
    """
    if obj is None:
        obj = {}
    if not isinstance(obj, dict):
        raise TypeError(f"expected a JSON object for {msg_type.__msgtype__}, got "
                        f"{type(obj).__name__}")
    fields = _fields(msg_type)
    if now is not None and "header" in fields:
        header = obj.get("header")
        if header is None:
            obj = {**obj, "header": {"stamp": to_json(now)}}
        elif isinstance(header, dict) and "stamp" not in header:
            obj = {**obj, "header": {**header, "stamp": to_json(now)}}
    for name, tp in fields.items():
        value = obj.get(name)
        if isinstance(value, str) and isinstance(tp, type) and issubclass(tp, UInt8Array):
            try:
                obj = {**obj, name: base64.b64decode(value, validate=True)}
            except binascii.Error as exc:
                raise TypeError(f"field {name!r}: not base64 ({exc})") from exc
    return from_builtins(obj, msg_type)


def request_args(args: Any, request_type: type[Message]) -> Any:
    """A ``call_service`` ``args`` as an object: a positional list maps to the fields in order."""
    if isinstance(args, list):
        names = list(_fields(request_type))
        if len(args) > len(names):
            raise TypeError(f"{request_type.__msgtype__} takes {len(names)} fields, got "
                            f"{len(args)} positional args")
        return dict(zip(names, args, strict=False))
    return args
