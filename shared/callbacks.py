"""Wrapping user callbacks: errors are logged (never raised into Zenoh), groups serialize,
and `async def` callbacks run in order on the executor with a keep-last backlog."""

from __future__ import annotations

import asyncio
import inspect
import logging
from collections import deque
from collections.abc import Callable
from typing import Any

from .executor import CallbackGroup, Executor, ReentrantCallbackGroup
from .log import ErrorLog

__all__ = ["make_dispatch"]


def make_dispatch(
    fn: Callable[[Any], Any],
    *,
    executor: Executor,
    logger: logging.Logger,
    what: str,
    group: CallbackGroup | None = None,
    depth: int = 10,
    errors: ErrorLog | None = None,
) -> Callable[[Any], None]:
    """Return ``dispatch(arg)``, safe to call from any thread, that runs ``fn(arg)``.

    A sync ``fn`` runs right away on the calling thread (inside ``group``'s lock if any).
    An ``async def fn`` is queued (at most ``depth`` pending, the oldest dropped) and run one
    at a time, in arrival order, on the executor's loop. Exceptions ``fn`` raises are
    counted in ``errors`` and logged with their traceback, rate-limited per exception type.
    """
    errs = errors if errors is not None else ErrorLog(logger)

    def report(exc: Exception) -> None:
        errs.report(type(exc).__name__, logging.ERROR, "%s callback raised %s: %s", what,
                    type(exc).__name__, exc, exc_info=exc)

    if inspect.iscoroutinefunction(fn):
        return _AsyncDispatch(fn, executor, logger, what, group, depth, report)
    if group is None or type(group) is ReentrantCallbackGroup:

        def dispatch(arg: Any) -> None:
            try:
                fn(arg)
            except Exception as exc:  # noqa: BLE001 user code never raises into Zenoh
                report(exc)

        return dispatch

    run = group.run

    def dispatch_grouped(arg: Any) -> None:
        try:
            run(fn, arg)
        except Exception as exc:  # noqa: BLE001 user code never raises into Zenoh
            report(exc)

    return dispatch_grouped


class _AsyncDispatch:
    def __init__(
        self,
        fn: Callable[[Any], Any],
        executor: Executor,
        logger: logging.Logger,
        what: str,
        group: CallbackGroup | None,
        depth: int,
        report: Callable[[Exception], None],
    ) -> None:
        self.fn = fn
        self.report = report
        self.executor = executor
        self.logger = logger
        self.what = what
        self.group = group
        self.pending: deque[Any] = deque(maxlen=depth)
        self.running = False
        self.dropped = 0

    def __call__(self, arg: Any) -> None:
        self.executor.call_soon(self._enqueue, arg)

    def _enqueue(self, arg: Any) -> None:
        if len(self.pending) == self.pending.maxlen:
            self.dropped += 1
            if self.dropped == 1 or self.dropped % 100 == 0:
                self.logger.warning(
                    "%s: async callback backlog full, dropped %d oldest", self.what, self.dropped
                )
        self.pending.append(arg)
        if not self.running:
            self.running = True
            asyncio.get_running_loop().create_task(self._drain())

    async def _drain(self) -> None:
        try:
            while self.pending:
                arg = self.pending.popleft()
                try:
                    await self.fn(arg)
                except Exception as exc:  # noqa: BLE001 user code never stops the queue
                    self.report(exc)
                self.executor.mark_work()
        finally:
            self.running = False
