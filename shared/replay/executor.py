"""`DeterministicExecutor`: the executor's asyncio loop, stepped by the run instead of a thread."""

from __future__ import annotations

import asyncio
import logging
import threading

from ..executor import Executor

__all__ = ["DeterministicExecutor"]

_log = logging.getLogger("zenros.replay")


class DeterministicExecutor(Executor):
    """An `Executor` with no thread: `drain` runs every ready callback on the caller's thread.

    Timers and ``async def`` callbacks are queued on the loop as usual (``call_soon``,
    ``submit``); they run only when the run drains the loop, in the order they were queued,
    and the loop never waits on the wall clock. A callback scheduled for a wall-clock time
    (``asyncio.sleep``, ``loop.call_later``) is reported once: it would fire whenever the
    wall clock says, and a deterministic node must not use one.
    """

    def __init__(self, name: str = "zenros-replay") -> None:  # no thread started
        self.loop = asyncio.new_event_loop()
        self._done = threading.Event()
        self._work = threading.Condition()
        self._work_count = 0
        self._thread = threading.current_thread()
        self._warned_wall = False

    def drain(self) -> int:
        """Run the loop until no callback is ready; returns how many loop passes it took."""
        loop = self.loop
        passes = 0
        while loop._ready:  # type: ignore[attr-defined]  # asyncio's own ready queue
            loop.call_soon(loop.stop)
            loop.run_forever()
            passes += 1
        if loop._scheduled and not self._warned_wall:  # type: ignore[attr-defined]
            self._warned_wall = True
            _log.warning("a wall-clock asyncio timer (asyncio.sleep, call_later) is pending in "
                         "a deterministic run: it fires on the wall clock, so outputs may "
                         "differ from run to run (docs/replay.md)")
        return passes

    @property
    def in_loop_thread(self) -> bool:
        return threading.current_thread() is self._thread

    def stop(self, timeout: float = 2.0) -> None:
        """Cancel what is pending and close the loop."""
        if self.loop.is_closed():
            return
        tasks = asyncio.all_tasks(self.loop)
        for t in tasks:
            t.cancel()
        if tasks:
            self.loop.run_until_complete(asyncio.gather(*tasks, return_exceptions=True))
        self.loop.close()
        self._done.set()
