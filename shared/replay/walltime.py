"""`WallClockCheck`: reports wall-clock reads and unseeded randomness inside a deterministic run.

While the run dispatches (a message, a timer), ``time.time``, ``time.monotonic``,
``time.perf_counter`` (and their ``_ns`` forms), ``uuid.uuid4`` and ``os.urandom`` are
wrapped: a call whose caller is not on the allowed list (the standard library's
logging, which stamps records, and zenros's own plumbing) is logged once per calling line
with that line, and counted. Callers a node declares exempt (nav's planner measures its planning time for the
ComputePathToPose result, which no topic carries) are not reported. The call still returns
the real value: the check reports,
it does not change behaviour. A name imported before the run (``from time import
monotonic``) is not seen; docs/replay.md says so.
"""

from __future__ import annotations

import logging
import os
import sys
import threading
import time
import uuid
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from types import ModuleType
from typing import Any

__all__ = ["WallClockCheck", "WallRead"]

_log = logging.getLogger("zenros.replay")

_WATCHED: tuple[tuple[ModuleType, str], ...] = (
    (time, "time"), (time, "time_ns"), (time, "monotonic"), (time, "monotonic_ns"),
    (time, "perf_counter"), (time, "perf_counter_ns"), (uuid, "uuid4"), (os, "urandom"),
)
# Callers whose reads never reach a node's outputs: log records' own stamps, threading's
# waits, the run's plumbing. Matched against the caller's file path.
_ALLOWED = (os.sep + "logging" + os.sep, os.sep + "threading.py", os.sep + "asyncio" + os.sep,
            os.sep + "zenros" + os.sep + "replay" + os.sep, os.sep + "shared" + os.sep + "replay"
            + os.sep, os.sep + "queue.py", os.sep + "selectors.py")


class WallRead(tuple[str, str, int]):
    """(function, file, line) of one reported read."""

    __slots__ = ()


class WallClockCheck:
    """Installed for a run's life (`install`, `uninstall`), reporting only while a dispatch
    runs (`watching`); ``reads`` lists each calling line once, ``count`` every call."""

    def __init__(self, logger: logging.Logger = _log,
                 exempt: dict[str, str] | None = None) -> None:
        self.exempt = dict(exempt or {})
        """Path fragments of callers whose reads are known not to reach outputs, with why."""
        self.reads: list[WallRead] = []
        self.count = 0
        self._seen: set[tuple[str, int]] = set()
        self._logger = logger
        self._depth = 0
        self._thread = 0  # the dispatching thread
        self._originals: list[tuple[ModuleType, str, Callable[..., Any]]] = []

    def install(self) -> None:
        """Wrap the watched functions (once; they report only inside `watching`)."""
        if self._originals:
            return
        self._originals = [(mod, name, getattr(mod, name)) for mod, name in _WATCHED]
        for mod, name, fn in self._originals:
            setattr(mod, name, self._wrap(f"{mod.__name__}.{name}", fn))

    def uninstall(self) -> None:
        """Put the watched functions back."""
        originals, self._originals = self._originals, []
        for mod, name, fn in originals:
            setattr(mod, name, fn)

    @contextmanager
    def watching(self) -> Iterator[None]:
        """Report reads for the duration of the block (re-entrant; installs if need be)."""
        self.install()
        self._thread = threading.get_ident()
        self._depth += 1
        try:
            yield
        finally:
            self._depth -= 1

    def _wrap(self, what: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        def watched(*args: Any, **kwargs: Any) -> Any:
            if not self._depth or threading.get_ident() != self._thread:
                return fn(*args, **kwargs)  # not in a dispatch, or another thread
            frame = sys._getframe(1)
            where = frame.f_code.co_filename
            if not any(a in where for a in _ALLOWED) and not any(
                    e in where for e in self.exempt):
                self._report(what, where, frame.f_lineno)
            return fn(*args, **kwargs)

        watched.__wrapped__ = fn  # type: ignore[attr-defined]
        return watched

    def _report(self, what: str, where: str, line: int) -> None:
        self.count += 1
        if (where, line) in self._seen:
            return
        self._seen.add((where, line))
        self.reads.append(WallRead((what, where, line)))
        self._logger.warning("deterministic run: %s() read at %s:%d inside a callback; what "
                             "it returns differs from run to run (docs/replay.md)",
                             what, where, line)
