"""Rigs shared by the integration tests: a rosbridge server on a free port, a robot-side node,
a roslibpy client; a gateway (token check off), an HTTP client of its REST API, and the tasks
service behind it. A module
that needs another shape defines its own fixture of the same name (pytest takes the module's).
The simulated robot (chassis, nav, tasks, a gateway) is `sim_robot.py`'s."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
import roslibpy
from zenros.context import Context
from zenros.node import Node
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.rosbridge import RosbridgeServer
from zenros.services.gateway.testing import running_gateway
from zenros.services.tasks.node import TasksNode
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


@pytest.fixture
def gw(ctx_pair: list[Context], tmp_path: Path) -> Iterator[GatewayNode]:
    """A gateway on the first session, token check off, its settings under ``tmp_path``."""
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True) as node:
        yield node


@pytest.fixture
def http(gw: GatewayNode) -> Iterator[httpx.Client]:
    """An HTTP client of ``gw``'s REST API (``/api/v1``)."""
    with httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=15) as c:
        yield c


@pytest.fixture
def tasks(ctx_pair: list[Context], tmp_path: Path, gw: GatewayNode) -> Iterator[TasksNode]:
    """The tasks service on the second session (its files under ``tmp_path/t``), once the
    gateway sees it."""
    node = TasksNode(context=ctx_pair[1], parameter_overrides={"data_dir": str(tmp_path / "t")})
    assert gw.graph.wait_for_service("/tasks/create", 10)
    yield node
    node.close()
