"""Test support: a `GatewayNode` on free loopback ports, and a null-modem pty pair."""

from __future__ import annotations

import os
import select
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from zenros.context import Context

from .node import GatewayNode

__all__ = ["NullModem", "running_gateway"]


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
