"""`InputDecoder`: a bag's recorded payloads back into messages, one decoder per channel."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..bag.reader import BagMessage
from ..bag.schema import JSON_ENCODING, MSGPACK_ENCODING
from ..bag.transcode import TRANSCODED
from ..codec import _json_decoder, codec_for, split_encoding
from ..errors import ZenrosError
from ..registry import lookup_type

__all__ = ["InputDecoder", "UndecodableChannel"]


class UndecodableChannel(ZenrosError, ValueError):
    """A channel whose type or encoding this process cannot turn into a message."""


def channel_type_name(m: BagMessage) -> str:
    """The ROS type name of a message's channel: the Zenoh encoding's schema half, else the
    MCAP schema's name."""
    _, name = split_encoding(m.channel.metadata.get("zenoh_encoding", ""))
    return name or (m.schema.name if m.schema is not None else "")


class InputDecoder:
    """``decode(m)`` gives the message of a `BagMessage`; a channel that cannot be decoded
    raises `UndecodableChannel` (once per channel: the caller may skip that topic)."""

    def __init__(self) -> None:
        self._by_channel: dict[int, Callable[[bytes], Any]] = {}

    def type_name(self, m: BagMessage) -> str:
        return channel_type_name(m)

    def decode(self, m: BagMessage) -> Any:
        fn = self._by_channel.get(m.channel.id)
        if fn is None:
            fn = self._by_channel[m.channel.id] = self._decoder(m)
        return fn(m.data)

    def _decoder(self, m: BagMessage) -> Callable[[bytes], Any]:
        topic, name = m.channel.topic, channel_type_name(m)
        if not name:
            raise UndecodableChannel(f"{topic}: the bag names no message type")
        try:
            codec = codec_for(lookup_type(name))
        except LookupError:
            raise UndecodableChannel(f"{topic}: unknown message type {name!r}") from None
        enc = m.channel.message_encoding
        natural = MSGPACK_ENCODING if codec.bulk else JSON_ENCODING
        if enc == natural and TRANSCODED not in m.channel.metadata:
            return codec.decode
        if enc == JSON_ENCODING:  # a bulk type stored as JSON (bag record --bulk-json)
            return _json_decoder(codec.type)
        raise UndecodableChannel(f"{topic}: {name} in encoding {enc!r} (zenros reads "
                                 f"{natural})")
