"""rosbridge ``fragment`` frames: splitting large outgoing frames, joining incoming ones."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from .convert import dumps

__all__ = ["Defragmenter", "FragmentError", "fragment"]

_seed = itertools.count()


def fragment(frame: bytes, size: int, mid: Any = None) -> list[bytes]:
    """``frame`` split into ``fragment`` frames of at most ``size`` characters of JSON text.

    A frame no longer than ``size`` is returned as is. ``mid`` names the fragments (the
    message's id); without one a counter does, as in rosbridge.
    """
    if size <= 0 or len(frame) <= size:
        return [frame]
    text = frame.decode()
    if len(text) <= size:
        return [frame]
    if mid is None:
        mid = next(_seed)
    total = math.ceil(len(text) / size)
    return [dumps({"op": "fragment", "id": mid, "data": text[i * size:(i + 1) * size],
                   "num": i, "total": total}) for i in range(total)]


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
