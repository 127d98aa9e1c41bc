"""Test support: a `GatewayNode` on free loopback ports, and a stand-in robot's topics."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from zenros.context import Context

from .node import GatewayNode

__all__ = ["running_gateway"]


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
