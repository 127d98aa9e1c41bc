"""§3.3's restart_robot and shutdown without a launch to act on: a 503 naming the missing
service and how to get one, never a fake success (with a launch: tests/system/
test_launch_control.py)."""

from __future__ import annotations

import httpx
from zenros.services.gateway.node import GatewayNode


def test_without_a_launch_the_host_operations_are_503(gw: GatewayNode,
                                                       http: httpx.Client) -> None:
    for path, what in (("/system/restart_robot", "restart"), ("/system/shutdown", "shut down")):
        r = http.get(path)
        body = r.json()
        assert r.status_code == 503, r.text
        assert body["description"].startswith(f"no launch to {what}: /launch/"), body
        assert "zenros launch" in body["description"], body
    assert http.get("/system/restart_robot", params={"now": 1}).status_code == 400
