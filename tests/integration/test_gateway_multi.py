"""One gateway per robot namespace: each serves its own robot's topics on its own ports."""

from __future__ import annotations

from pathlib import Path

import httpx
from zenros.context import Context
from zenros.msgs.sensor_msgs import BatteryState
from zenros.services.gateway.testing import running_gateway
from zenros.testing import wait_for


def test_two_robots_two_gateways(ctx_pair: list[Context], tmp_path: Path,
                                 make_node: object) -> None:
    fleet = make_node("fleet", 1)  # type: ignore[operator]
    b1 = fleet.create_publisher(BatteryState, "/robot1/battery_state", 10)
    b2 = fleet.create_publisher(BatteryState, "/robot2/battery_state", 10)
    with running_gateway(ctx_pair[0], tmp_path / "1", namespace="/robot1",
                         no_token_check=True) as g1, \
            running_gateway(ctx_pair[0], tmp_path / "2", namespace="/robot2",
                            no_token_check=True) as g2:
        assert g1.fqn == "/robot1/gateway" and g2.fqn == "/robot2/gateway"
        assert len({g1.rest_port, g2.rest_port, g1.ws_port, g2.ws_port}) == 4
        assert b1.wait_for_subscribers(1, 5) and b2.wait_for_subscribers(1, 5)

        def power(port: int) -> float:
            st = httpx.get(f"http://127.0.0.1:{port}/api/v1/system/galileo_status").json()
            return float(st["power"])

        assert wait_for(lambda: (b1.publish(BatteryState(voltage=24.0)),
                                 b2.publish(BatteryState(voltage=36.0)))
                        and power(g1.rest_port) == 24.0 and power(g2.rest_port) == 36.0, 5)
        assert g1.core.identity.id != g2.core.identity.id
        assert g1.graph.wait_for(lambda: bool(g1.graph.publishers("/robot2/galileo/status")), 5)
