"""`Discovery`: the docs/robot-api.md §1.3 UDP broadcast (``id``, ``port``, ``mac``, ``version``)
once a second."""

from __future__ import annotations

import asyncio
import json
import logging
import socket

from ..state.core import Core

__all__ = ["Discovery", "discovery_payload"]


def discovery_payload(core: Core) -> bytes:
    ident = core.identity
    return json.dumps({"id": ident.id, "port": ident.port, "mac": ident.mac,
                       "version": ident.version}).encode()


class Discovery:
    """Sends the payload to ``address:port`` every ``period`` seconds from the gateway loop."""

    def __init__(self, core: Core, address: str, port: int, logger: logging.Logger,
                 period: float = 1.0) -> None:
        self.core = core
        self.target = (address, port)
        self.period = period
        self.logger = logger
        self.sent = 0
        self._sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
        self._sock.setblocking(False)
        self._task: asyncio.Task[None] | None = None
        self._failing = False

    async def start(self) -> None:
        self._task = asyncio.get_running_loop().create_task(self._loop())

    async def _loop(self) -> None:
        while True:
            try:
                self._sock.sendto(discovery_payload(self.core), self.target)
                self.sent += 1
                if self._failing:
                    self.logger.info("discovery broadcast to %s:%d works again", *self.target)
                self._failing = False
            except OSError as exc:
                if not self._failing:
                    self.logger.warning("discovery broadcast to %s:%d failed: %s; retrying",
                                        *self.target, exc)
                self._failing = True
            await asyncio.sleep(self.period)

    async def stop(self) -> None:
        if self._task is not None:
            self._task.cancel()
            await asyncio.gather(self._task, return_exceptions=True)
        self._sock.close()
