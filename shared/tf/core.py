"""`BufferCore`: non-blocking tf2 queries over a `FrameStore`, fast path first.

A query first tries the pair's cached `Chain`; when there is none (or it cannot answer),
it walks the tree as tf2 does (``walk``), which also produces tf2's exact errors.
The methods here expect the caller to hold the lock.
"""

from __future__ import annotations

from ..errors import TransformException
from .chain import Chain, NoChain, build_chain
from .report import frame_error, frame_listing
from .rigid import IDENTITY, Tf
from .store import DEFAULT_CACHE_TIME, FrameStore
from .walk import latest_common_time, walk

_MAX_CHAINS = 4096

__all__ = ["DEFAULT_CACHE_TIME", "BufferCore"]


class BufferCore(FrameStore):
    """Answers ``lookup`` and ``can`` queries at once (no waiting); see `Buffer`."""

    def _chain(self, target: str, source: str) -> Chain | NoChain:
        if len(self._chains) >= _MAX_CHAINS:
            self._chains.clear()
        ch = build_chain(self._caches, target, source, len(self._frames))
        self._chains[(target, source)] = ch
        return ch

    def _lookup(self, target: str, source: str, t: int, fn: str = "lookupTransform") -> tuple[Tf, int]:
        """``(T_target_source, stamp)`` at ``t`` (0: latest common time)."""
        ch = self._chains.get((target, source))
        if ch is None:
            if target == source:
                cache = self._caches.get(target)
                return IDENTITY, (t or (cache.newest() if cache is not None else 0))
            self._check(target, fn + " argument target_frame")
            self._check(source, fn + " argument source_frame")
            ch = self._chain(target, source)
        if isinstance(ch, Chain):
            tt = t or ch.latest_time()
            if tt:
                r = ch.evaluate(tt)
                if r is not None:
                    return r, tt
            elif not ch.dyn:
                return ch.evaluate(0) or IDENTITY, 0
        return self._walk(target, source, t)

    def _walk(self, target: str, source: str, t: int) -> tuple[Tf, int]:
        limit = len(self._frames)
        if t == 0:
            t = latest_common_time(self._caches, target, source, limit, self._dump)
        return walk(self._caches, target, source, t, limit, self._dump), t

    def _can(self, target: str, source: str, t: int) -> bool:
        """canTransform without strings: the fast negative path."""
        ch = self._chains.get((target, source))
        if ch is None:
            if target == source:
                return True
            if frame_error(target, "") or frame_error(source, ""):
                return False
            if target not in self._frames or source not in self._frames:
                return False
            ch = self._chain(target, source)
        if isinstance(ch, Chain):
            tt = t or ch.latest_time()
            if tt or not ch.dyn:
                return ch.covers(tt) if tt else True
        elif ch.disjoint:
            return False
        try:
            self._walk(target, source, t)
        except TransformException:
            return False
        return True

    def _can_explain(self, target: str, source: str, t: int) -> str:
        """Why canTransform is false, in tf2's words ("" if it is true)."""
        if target == source:
            return ""
        missing = [
            p for p in (self._frame_problem(target, "canTransform argument target_frame"),
                        self._frame_problem(source, "canTransform argument source_frame"))
            if p
        ]  # fmt: skip
        if missing:
            return "\n".join(missing)
        try:
            self._lookup(target, source, t, "canTransform")
        except TransformException as e:
            return str(e)
        return ""

    def _frame_problem(self, frame: str, arg: str) -> str:
        """What is wrong with a frame id given to a query ("" if nothing)."""
        err = frame_error(frame, arg)
        if err is not None:
            return str(err)
        if frame not in self._frames:
            return (
                f'Invalid frame ID "{frame}" passed to {arg} - frame does not exist. '
                f"Known frames: {frame_listing(self._frames)}"
            )
        return ""

    def _latest_or_zero(self, target: str, source: str) -> int:
        """The latest common time, or 0 if there is none (yet)."""
        try:
            return latest_common_time(
                self._caches, target, source, len(self._frames), self._dump
            )
        except TransformException:
            return 0
