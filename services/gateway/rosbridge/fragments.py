"""rosbridge ``fragment`` frames: splitting large outgoing frames, joining incoming ones."""

from __future__ import annotations

import itertools
import math
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, overload

from .convert import dumps

__all__ = ["Defragmenter", "FragmentError", "Fragments", "fragment"]

_seed = itertools.count()


class Fragments(Sequence[bytes]):
    """The ``fragment`` frames of one large frame, each made when first asked for.

    A 5 MB map in 20 fragments is not decoded and re-encoded in one go on the event loop
    (3 ms, during which no client got anything) but a piece at a time, as the writer sends
    them; clients of the same message share the pieces. An ASCII frame (msgspec's JSON of
    numbers) is cut by bytes, which are its characters; any other is decoded once."""

    def __init__(self, frame: bytes, size: int, mid: Any) -> None:
        self.frame, self.size, self.mid = frame, size, mid
        self._text = None if frame.isascii() else frame.decode()
        length = len(frame) if self._text is None else len(self._text)
        self.total = math.ceil(length / size)
        self._made: list[bytes | None] = [None] * self.total

    def __len__(self) -> int:
        return self.total

    @overload
    def __getitem__(self, i: int) -> bytes: ...

    @overload
    def __getitem__(self, i: slice) -> list[bytes]: ...

    def __getitem__(self, i: int | slice) -> bytes | list[bytes]:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(self.total))]
        if i < 0:
            i += self.total
        piece = self._made[i]  # IndexError out of range, as a list
        if piece is None:
            cut = slice(i * self.size, (i + 1) * self.size)
            data = self.frame[cut].decode() if self._text is None else self._text[cut]
            piece = self._made[i] = dumps({"op": "fragment", "id": self.mid, "data": data,
                                           "num": i, "total": self.total})
        return piece


_recent: deque[Fragments] = deque(maxlen=4)
"""The last frames split (held, so ``is`` cannot match a new frame at a reused address)."""


def fragment(frame: bytes, size: int, mid: Any = None) -> Sequence[bytes]:
    """``frame`` split into ``fragment`` frames of at most ``size`` characters of JSON text.

    A frame no longer than ``size`` is returned as is. ``mid`` names the fragments (the
    message's id); without one a counter does, as in rosbridge. The same frame split again
    (the same message to another client) gives the same pieces.
    """
    if size <= 0 or len(frame) <= size:
        return [frame]
    for done in _recent:
        if done.frame is frame and done.size == size and (mid is None or mid == done.mid):
            return done
    if not frame.isascii() and len(frame.decode()) <= size:
        return [frame]
    pieces = Fragments(frame, size, next(_seed) if mid is None else mid)
    _recent.append(pieces)
    return pieces


class FragmentError(ValueError):
    """A fragment frame that cannot be used (bad fields, inconsistent totals)."""


@dataclass
class _Partial:
    total: int
    started: float
    parts: dict[int, str] = field(default_factory=dict)


class Defragmenter:
    """Collects incoming ``fragment`` frames by id; a complete set gives the original text.

    Args:
        clock: monotonic seconds.
        timeout: seconds after which an incomplete message is forgotten (rosbridge's
            ``fragment_timeout``, 600 s by default).
    """

    def __init__(self, clock: Callable[[], float], timeout: float = 600.0) -> None:
        self._clock = clock
        self._timeout = timeout
        self._partial: dict[Any, _Partial] = {}

    def add(self, frame: dict[str, Any]) -> str | None:
        """Add one fragment; the joined JSON text once all parts are in, else None.

        Raises:
            FragmentError: missing or ill-typed ``id``/``data``/``num``/``total``.
        """
        self._expire()
        mid, data, num, total = (frame.get(k) for k in ("id", "data", "num", "total"))
        if mid is None or not isinstance(data, str):
            raise FragmentError("fragment needs an 'id' and a string 'data'")
        if not isinstance(num, int) or not isinstance(total, int) or not 0 <= num < total:
            raise FragmentError(f"fragment needs integers 0 <= num < total, got num={num!r} "
                                f"total={total!r}")
        key = mid if isinstance(mid, (str, int)) else repr(mid)
        part = self._partial.get(key)
        if part is None or part.total != total:
            part = self._partial[key] = _Partial(total, self._clock())
        part.parts[num] = data
        if len(part.parts) < total:
            return None
        del self._partial[key]
        return "".join(part.parts[i] for i in range(total))

    def _expire(self) -> None:
        limit = self._clock() - self._timeout
        for key in [k for k, p in self._partial.items() if p.started < limit]:
            del self._partial[key]

    def __len__(self) -> int:
        return len(self._partial)
