"""Bulk (MessagePack) payloads as JSON in a bag, for viewers that only read JSON (Foxglove),
and back to MessagePack for playback. Used only with ``zenros bag record --bulk-json``."""

from __future__ import annotations

from collections.abc import Callable
from functools import cache

import msgspec

from ..codec import _json_decoder, codec_for, to_builtins
from ..registry import lookup_type

__all__ = ["TRANSCODED", "from_json", "to_json"]

TRANSCODED = "transcoded_from"  # channel metadata key: the encoding the payloads travelled in

Transcoder = Callable[[bytes], bytes | None]


@cache
def to_json(type_name: str) -> Transcoder | None:
    """MessagePack -> JSON for a bulk type (None for other types); None for a bad payload."""
    try:
        codec = codec_for(lookup_type(type_name))
    except LookupError:
        return None
    if not codec.bulk:
        return None
    encode = msgspec.json.Encoder().encode

    def transcode(data: bytes) -> bytes | None:
        try:
            out: bytes = encode(to_builtins(codec.decode(data)))
        except (ValueError, TypeError):
            return None
        return out

    return transcode


@cache
def from_json(type_name: str) -> Transcoder:
    """JSON (as `to_json` wrote it) -> MessagePack, as the type travels on the wire."""
    codec = codec_for(lookup_type(type_name))
    decode = _json_decoder(codec.type)

    def transcode(data: bytes) -> bytes | None:
        try:
            return codec.encode(decode(data))
        except (ValueError, TypeError, msgspec.DecodeError):
            return None

    return transcode
