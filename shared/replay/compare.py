"""`compare_bags`: whether two replays' outputs are the same, and if not, where they first
differ: the topic, the time, the field path and both values."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..bag.reader import BagMessage, bag_files, iter_messages, resolve_bag
from ..codec import to_builtins
from .inputs import InputDecoder, UndecodableChannel

__all__ = ["Difference", "compare_bags", "first_field_difference"]


@dataclass(frozen=True)
class Difference:
    """The first message at which two bags differ. ``index``: its position (0-based) in
    log-time order; ``a``/``b``: the two values at ``path`` (None where a bag has no
    message there)."""

    index: int
    topic: str
    time_ns: int
    path: str
    a: Any
    b: Any

    def __str__(self) -> str:
        return (f"first difference at message {self.index}: {self.topic} at "
                f"{self.time_ns / 1e9:.9f} s, {self.path}: {self.a!r} != {self.b!r}")


def _messages(path: Path) -> Any:
    return iter_messages(bag_files(resolve_bag(str(path))))


def compare_bags(a: Path, b: Path) -> Difference | None:
    """None if every message (topic, log time, type, content) matches in order; else the
    first `Difference`. Content is compared field by field after decoding (bit-exact for
    floats: a NaN equals a NaN), raw bytes where a channel's type is unknown."""
    dec_a, dec_b = InputDecoder(), InputDecoder()
    it_a, it_b = _messages(a), _messages(b)
    index = 0
    while True:
        ma: BagMessage | None = next(it_a, None)
        mb: BagMessage | None = next(it_b, None)
        if ma is None and mb is None:
            return None
        if ma is None or mb is None:
            m = ma or mb
            assert m is not None
            return Difference(index, m.channel.topic, m.log_time, "(message)",
                              None if ma is None else m.channel.topic,
                              None if mb is None else m.channel.topic)
        for path, va, vb in (("(topic)", ma.channel.topic, mb.channel.topic),
                             ("(log_time)", ma.log_time, mb.log_time),
                             ("(type)", dec_a.type_name(ma), dec_b.type_name(mb))):
            if va != vb:
                return Difference(index, ma.channel.topic, ma.log_time, path, va, vb)
        if ma.data != mb.data:
            diff = _content_difference(dec_a, dec_b, ma, mb)
            return Difference(index, ma.channel.topic, ma.log_time, *diff)
        index += 1


def _content_difference(dec_a: InputDecoder, dec_b: InputDecoder, ma: BagMessage,
                        mb: BagMessage) -> tuple[str, Any, Any]:
    try:
        va, vb = to_builtins(dec_a.decode(ma)), to_builtins(dec_b.decode(mb))
    except (UndecodableChannel, ValueError, TypeError):
        return "(bytes)", ma.data[:32].hex(), mb.data[:32].hex()
    found = first_field_difference(va, vb)
    return found if found is not None else ("(encoding)", ma.data[:32].hex(),
                                            mb.data[:32].hex())


def first_field_difference(a: Any, b: Any, path: str = "") -> tuple[str, Any, Any] | None:
    """The first (path, a, b) where two decoded messages differ (``.linear.x``,
    ``.poses[3].pose.position.y``), or None."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in list(a) + [k for k in b if k not in a]:
            if k not in a or k not in b:
                return (f"{path}.{k}", a.get(k), b.get(k))
            found = first_field_difference(a[k], b[k], f"{path}.{k}")
            if found is not None:
                return found
        return None
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        for i, (x, y) in enumerate(zip(a, b, strict=False)):
            found = first_field_difference(x, y, f"{path}[{i}]")
            if found is not None:
                return found
        if len(a) != len(b):
            return (f"{path}.length", len(a), len(b))
        return None
    if isinstance(a, float) and isinstance(b, float):
        same = (math.isnan(a) and math.isnan(b)) or a.hex() == b.hex()
        return None if same else (path or "(value)", a, b)
    if type(a) is not type(b) or a != b:
        return (path or "(value)", a, b)
    return None
