"""`FrontEnds`: the gateway's doors as its node runs them, each with a start and a stop (as
uvicorn's startup and shutdown): started in order, stopped in reverse when the node closes.

A front end is anything with a ``name``, ``start()`` and ``stop()``; either may be a
coroutine function (run on the gateway's loop) or a plain one (run where the node calls it).
`Door` makes one of two callables, `AsgiServer` is an ASGI app served by uvicorn.
"""

from __future__ import annotations

import asyncio
import inspect
import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import uvicorn
from starlette.types import ASGIApp

from .runner import AsyncRunner, bind_tcp, start_uvicorn

__all__ = ["STOP_TIMEOUT", "AsgiServer", "Door", "FrontEnd", "FrontEnds"]

STOP_TIMEOUT = 8.0  # s a front end's stop may take on the loop


class FrontEnd(Protocol):
    """A door of the gateway: ``start()`` once, ``stop()`` when the node closes."""

    @property
    def name(self) -> str: ...
    def start(self) -> object: ...
    def stop(self) -> object: ...


@dataclass(frozen=True)
class Door:
    """A front end made of two callables (a door whose own methods take arguments)."""

    name: str
    start: Callable[[], object]
    stop: Callable[[], object]


class AsgiServer:
    """An ASGI app served by uvicorn on the gateway's loop; its socket is bound when it is
    made, so `port` is known before it starts.

    Raises:
        ConfigError: the port cannot be bound.
    """

    def __init__(self, name: str, app: ASGIApp, host: str, port: int, **kw: Any) -> None:
        self.name = name
        self.app = app
        self.sock = bind_tcp(host, port)
        self.port: int = self.sock.getsockname()[1]
        self._kw = kw
        self._server: uvicorn.Server | None = None
        self._task: asyncio.Task[None] | None = None

    async def start(self) -> None:
        try:
            self._server, self._task = await start_uvicorn(self.app, self.sock, **self._kw)
        except BaseException:
            self.sock.close()
            raise

    async def stop(self) -> None:
        if self._server is not None and self._task is not None:
            self._server.should_exit = True
            await asyncio.gather(self._task, return_exceptions=True)
        self.sock.close()


class FrontEnds:
    """The started front ends, in order; `stop` stops them in reverse, each whatever the
    others do (a failure is logged)."""

    def __init__(self, runner: AsyncRunner, logger: logging.Logger) -> None:
        self.runner = runner
        self.logger = logger
        self.started: list[FrontEnd] = []

    def _run(self, result: object, timeout: float) -> None:
        if inspect.iscoroutine(result):
            self.runner.call(result, timeout)

    def start(self, end: FrontEnd) -> None:
        """Start ``end`` (after those started before it); it is stopped before them.

        Raises:
            whatever its start raises (it is not kept then).
        """
        self._run(end.start(), 10.0)
        self.started.append(end)

    def stop(self) -> None:
        while self.started:
            end = self.started.pop()
            try:
                self._run(end.stop(), STOP_TIMEOUT)
            except Exception:
                self.logger.exception("stopping the %s front end failed", end.name)
