"""`NativeCommands`: executes docs/robot-api.md §12.3 native command bytes (from
``galileo/cmds``)."""

from __future__ import annotations

import asyncio
import concurrent.futures
import logging
from collections.abc import Coroutine
from typing import Any, Protocol

from ..state.core import Core, NavUnavailable

__all__ = ["MappingCommands", "NativeCommands"]


class MappingCommands(Protocol):
    """The map building operations ``'V'`` commands run (the REST routes' own:
    `zenros.services.gateway.http.routes.mapping.NativeMapping`)."""

    def start(self) -> Coroutine[Any, Any, None]: ...

    def stop(self) -> Coroutine[Any, Any, None]: ...

    def save(self) -> Coroutine[Any, Any, None]: ...

    def update(self) -> Coroutine[Any, Any, None]: ...


class NativeCommands:
    """Interprets one command at a time; a command it cannot honour is logged, not faked."""

    def __init__(self, core: Core, logger: logging.Logger,
                 loop: asyncio.AbstractEventLoop,
                 mapping: MappingCommands | None = None) -> None:
        self.core = core
        self.logger = logger
        self.loop = loop
        self.mapping = mapping

    def __call__(self, data: bytes) -> bool:
        """Execute ``data``; True when it was understood and started."""
        try:
            return self._run(data)
        except (NavUnavailable, ValueError) as exc:
            self._refused(data, exc)
        return False

    def _refused(self, data: bytes, exc: BaseException) -> None:
        self.logger.warning("native command %s refused: %s", data.hex(" "), exc)

    def _start(self, data: bytes, coro: Coroutine[Any, Any, None]) -> None:
        """Run a navigation coroutine on the gateway's loop; report a refusal when it ends."""
        fut = asyncio.run_coroutine_threadsafe(coro, self.loop)

        def done(f: concurrent.futures.Future[None]) -> None:
            exc = f.exception()
            if exc is not None:
                self._refused(data, exc)

        fut.add_done_callback(done)

    def _run(self, data: bytes) -> bool:
        if not data:
            return False
        op, args = data[0], data[1:]
        s = self.core.state
        if op == ord("m") and args[:1] == b"\x00":
            self.core.navigation().open()
            return True
        if op == ord("m") and args[:1] == b"\x04":
            # as /navigation/stop: navStatus stays 0 through nav's next status updates
            if self.core.nav is not None:
                self._start(data, self.core.nav.stop())
            s.nav_open = False
            return True
        if op == ord("g") and len(args) == 1:
            self._start(data, self.core.navigation().goto_index(args[0]))
            return True
        if op == ord("i") and len(args) == 1 and args[0] <= 2:
            nav = self.core.navigation()
            self._start(data, (nav.pause, nav.resume, nav.cancel)[args[0]]())
            return True
        if op == ord("j") and args[:1] in (b"\x00", b"\x01"):
            nav = self.core.navigation()
            self._start(data, nav.go_charge() if args[0] == 0 else nav.stop_charge())
            return True
        if op == ord("V") and len(args) == 1 and args[0] <= 3 and self.mapping is not None:
            m = self.mapping
            self._start(data, (m.start, m.stop, m.save, m.update)[args[0]]())
            return True
        self.logger.warning("native command %s is not supported by this robot",
                            data.hex(" "))
        return False
