"""Publish time of a recorded sample: the message's ``header.stamp``, else the Zenoh source
timestamp, read without decoding the whole message into its type."""

from __future__ import annotations

from collections.abc import Callable
from functools import cache

import msgspec

from ..registry import lookup_type

__all__ = ["stamp_reader"]


class _Time(msgspec.Struct):
    sec: int = 0
    nanosec: int = 0


class _Header(msgspec.Struct):
    stamp: _Time = msgspec.field(default_factory=_Time)


class _Stamped(msgspec.Struct):
    header: _Header | None = None


StampReader = Callable[[bytes], int]


@cache
def stamp_reader(type_name: str, msgpack: bool) -> StampReader | None:
    """A function giving ``header.stamp`` in ns (0 if unreadable or zero) for types that have
    a top-level ROS 2 header; None for other types (use the source timestamp)."""
    try:
        fields = {f for f in lookup_type(type_name).__struct_fields__}
    except LookupError:
        return None
    if "header" not in fields:
        return None
    decoder = msgspec.msgpack.Decoder(_Stamped) if msgpack else msgspec.json.Decoder(_Stamped)
    decode = decoder.decode

    def read(data: bytes) -> int:
        try:
            h = decode(data).header
        except (msgspec.DecodeError, msgspec.ValidationError):
            return 0
        if h is None:
            return 0
        ns: int = h.stamp.sec * 1_000_000_000 + h.stamp.nanosec
        return ns

    return read
