"""docs/robot-api.md §6 ``GET /navigation/wind_info`` through a real server from the simulated
chassis's wind sensor: calm indoors, the configured wind outdoors, 404 without a sensor."""

from __future__ import annotations

from collections.abc import Iterator

import httpx
import pytest
from zenros.context import Context
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.testing import wait_for


@pytest.fixture
def windy(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_rate": 0.0, "wind_speed": 9.0, "wind_gust": 1.0, "wind_direction": 90.0,
        "seed": 2})
    yield node
    node.close()


def test_wind_info_without_a_sensor_is_a_404(gw: GatewayNode, http: httpx.Client) -> None:
    r = http.get("/navigation/wind_info")
    assert r.status_code == 404 and "wind" in r.json()["description"], r.text


def test_wind_info_reads_the_wind_sensor(windy: ChassisNode, gw: GatewayNode,
                                         http: httpx.Client) -> None:
    got: list[httpx.Response] = []

    def answered() -> bool:  # once the gateway's graph has heard of the chassis's topic
        got.append(http.get("/navigation/wind_info"))
        return got[-1].status_code == 200

    assert wait_for(answered, 20), got[-1].text
    r = got[-1]
    body = r.json()
    assert set(body) == {"current_speed", "max_speed", "level", "direction"}
    assert 4.0 < body["current_speed"] < 14.0 and body["max_speed"] >= body["current_speed"]
    assert body["level"] in (3.0, 4.0, 5.0, 6.0)
    assert 0.0 <= body["direction"] < 360.0 and abs(body["direction"] - 90.0) < 30.0
