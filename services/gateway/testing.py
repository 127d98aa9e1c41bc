"""Test support: a `GatewayNode` on free loopback ports, and a null-modem pty pair."""

from __future__ import annotations

import asyncio
import os
import select
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from zenros.context import Context

from .node import GatewayNode

if TYPE_CHECKING:
    import httpx

__all__ = ["AsgiClient", "NullModem", "running_gateway"]


@contextmanager
def running_gateway(ctx: Context, home: Path, **params: Any) -> Iterator[GatewayNode]:
    """A gateway on ``ctx`` with every port chosen free, its data under ``home``.

    ``params`` override the node parameters (e.g. ``no_token_check=True``).
    """
    namespace = params.pop("namespace", None)
    overrides: dict[str, Any] = {"rest_port": 0, "ws_port": 0, "modbus_port": 0,
                                 "rosbridge_port": 0,
                                 "discovery_port": -1, "config_file": str(home / "config.json"),
                                 "data_dir": str(home / "data")}
    overrides.update(params)
    node = GatewayNode(context=ctx, parameter_overrides=overrides, namespace=namespace)
    try:
        yield node
    finally:
        node.close()


class NullModem:
    """Two pty pairs joined master to master: a serial cable between two device paths."""

    def __init__(self) -> None:
        self.a_master, a_slave = os.openpty()
        self.b_master, b_slave = os.openpty()
        self.a, self.b = os.ttyname(a_slave), os.ttyname(b_slave)
        self._slaves = (a_slave, b_slave)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._relay, daemon=True)
        self._thread.start()

    def _relay(self) -> None:
        pairs = {self.a_master: self.b_master, self.b_master: self.a_master}
        while not self._stop.is_set():
            ready, _, _ = select.select(list(pairs), [], [], 0.05)
            for fd in ready:
                try:
                    os.write(pairs[fd], os.read(fd, 4096))
                except OSError:
                    pass

    def close(self) -> None:
        self._stop.set()
        self._thread.join(2)
        for fd in (self.a_master, self.b_master, *self._slaves):
            os.close(fd)


class AsgiClient:
    """A synchronous HTTP client that calls an ASGI app in process (no socket, no server):
    ``AsgiClient(node.http, "/api/v1").get("/token", params=...)`` answers as the gateway's
    REST port would, since it is the same app. Each request runs on a loop of its own."""

    def __init__(self, app: Any, base_path: str = "", timeout: float = 10.0) -> None:
        self.app, self.base_url, self.timeout = app, f"http://127.0.0.1{base_path}", timeout

    def request(self, method: str, url: str, **kw: Any) -> httpx.Response:
        import httpx  # the test extra's; imported here so the module needs it only in use

        async def call() -> httpx.Response:
            async with httpx.AsyncClient(transport=httpx.ASGITransport(app=self.app),
                                         base_url=self.base_url, timeout=self.timeout) as c:
                r = await c.request(method, url, **kw)
                await r.aread()
                return r

        return asyncio.run(call())

    def get(self, url: str, **kw: Any) -> httpx.Response:
        return self.request("GET", url, **kw)

    def put(self, url: str, **kw: Any) -> httpx.Response:
        return self.request("PUT", url, **kw)

    def post(self, url: str, **kw: Any) -> httpx.Response:
        return self.request("POST", url, **kw)

    def delete(self, url: str, **kw: Any) -> httpx.Response:
        return self.request("DELETE", url, **kw)
