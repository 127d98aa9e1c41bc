"""rosbridge and the dashboard inside the gateway: the page, its config.json and a roslibpy
client on the gateway's rosbridge port."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
import roslibpy
from zenros.context import Context
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway
from zenros.testing import roslibpy_connect, wait_for


@pytest.fixture
def gateway(ctx_pair: list[Context], tmp_path: Path) -> Iterator[GatewayNode]:
    with running_gateway(ctx_pair[0], tmp_path, namespace="/robot1") as node:
        yield node


def test_dashboard_is_served_with_its_config(gateway: GatewayNode) -> None:
    base = f"http://127.0.0.1:{gateway.rest_port}"
    page = httpx.get(base + "/", timeout=10)
    assert page.status_code == 200 and "text/html" in page.headers["content-type"]
    assert 'src="js/app.js"' in page.text
    assert gateway.rosbridge is not None
    assert httpx.get(base + "/config.json", timeout=10).json() == {
        "rosbridge_port": gateway.rosbridge.port, "namespace": "/robot1", "title": ""}
    for path in ("/style.css", "/js/app.js", "/js/map_view.js", "/js/rosbridge.js",
                 "/js/teleop.js", "/js/tasks.js"):
        assert httpx.get(base + path, timeout=10).status_code == 200, path
    assert httpx.get(base + "/nope.js", timeout=10).status_code == 404
    assert httpx.get(base + "/api/v1/system/status", timeout=10).status_code in (200, 401)


def test_roslibpy_on_the_gateway(gateway: GatewayNode, ctx_pair: list[Context]) -> None:
    assert gateway.rosbridge is not None
    robot = Node("chassis", namespace="/robot1", context=ctx_pair[1])
    try:
        pub = robot.create_publisher(String, "state_text")
        ros = roslibpy_connect("127.0.0.1", gateway.rosbridge.port)
        try:
            got: list[dict[str, str]] = []
            roslibpy.Topic(ros, "/robot1/state_text", "std_msgs/String").subscribe(got.append)
            assert pub.wait_for_subscribers(1, 10)
            assert wait_for(lambda: (pub.publish(String(data="ok")), bool(got))[1], 10)
            assert "/robot1/gateway" in ros.get_nodes()
        finally:
            ros.close()
    finally:
        robot.close()
