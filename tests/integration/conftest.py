"""Rigs shared by the rosbridge integration tests: a server on a free port, a robot-side node,
a roslibpy client. A module that needs another shape of server defines its own fixture of the
same name (pytest takes the module's)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
import roslibpy
from zenros.context import Context
from zenros.node import Node
from zenros.services.gateway.rosbridge import RosbridgeServer
from zenros.testing import roslibpy_connect

ROSBRIDGE_TIMEOUT = 10.0


@pytest.fixture
def server(ctx_pair: list[Context]) -> Iterator[RosbridgeServer]:
    """A rosbridge server on the first session, on a free port."""
    node = Node("rosbridge", context=ctx_pair[0])
    srv = RosbridgeServer(node, port=0)
    srv.start_in_thread()
    yield srv
    srv.stop_in_thread()
    node.close()


@pytest.fixture
def robot(ctx_pair: list[Context]) -> Iterator[Node]:
    """A node on the second session: the zenros side the clients reach through the server."""
    node = Node("robot", context=ctx_pair[1])
    yield node
    node.close()


@pytest.fixture
def ros(server: RosbridgeServer) -> Iterator[roslibpy.Ros]:
    """A connected roslibpy client of ``server``."""
    client = roslibpy_connect("127.0.0.1", server.port, ROSBRIDGE_TIMEOUT)
    yield client
    client.close()
