"""docs/robot-api.md §6.11 through a real gateway and a real elevator controller:
``get_elevator_info``, ``elevator_to_level``, ``elevator_open_door``; without a controller,
503 saying how to launch one."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from tiny_building import write_building
from zenros.context import Context
from zenros.services.elevator.node import ElevatorNode, elevator_key
from zenros.services.gateway.node import GatewayNode
from zenros.testing import wait_for

OPS: list[tuple[str, dict[str, Any]]] = [
    ("/navigation/get_elevator_info", {}), ("/navigation/elevator_to_level", {"level": 2}),
    ("/navigation/elevator_open_door", {"open": 1})]


@pytest.fixture
def controller(ctx_pair: list[Context], tmp_path: Path,
               gw: GatewayNode) -> Iterator[ElevatorNode]:
    node = ElevatorNode(context=ctx_pair[1], parameter_overrides={
        "building": str(write_building(tmp_path / "tower"))})
    assert gw.graph.wait_for_service(elevator_key("lift1", "command"), 10)
    yield node
    node.close()


def info(http: httpx.Client, **query: Any) -> dict[str, Any]:
    r = http.get("/navigation/get_elevator_info", params=query)
    assert r.status_code == 200, r.text
    body: dict[str, Any] = r.json()
    return body


def test_without_a_controller_the_operations_say_how_to_launch_one(
        http: httpx.Client) -> None:
    for op, query in OPS:
        r = http.get(op, params=query)
        assert r.status_code == 503, (op, r.text)
        assert "no building/elevator controller: launch with building:=" in r.text, r.text
    index = http.get("/").json()
    for op, _ in OPS:
        assert f"GET /api/v1{op}" in index["implemented"]


def test_info_to_level_and_doors(http: httpx.Client, controller: ElevatorNode) -> None:
    assert info(http) == {"level": 1, "direction": "STOP", "state": "NONE",
                          "front_door_open": False, "back_door_open": False, "name": "lift1"}
    assert info(http, elevator_name="lift1")["name"] == "lift1"
    r = http.get("/navigation/elevator_to_level", params={"elevator_name": "lift1", "level": 3})
    assert r.status_code == 200 and r.json() == {"result": True}, r.text
    assert wait_for(lambda: info(http)["front_door_open"], 15)
    assert info(http)["level"] == 3
    r = http.get("/navigation/elevator_to_level", params={"level": 1})
    assert r.json() == {"result": True}
    assert wait_for(lambda: info(http)["direction"] == "DONW", 15)  # the API's spelling
    assert wait_for(lambda: info(http)["level"] == 1 and info(http)["direction"] == "STOP", 15)
    assert wait_for(lambda: not info(http)["front_door_open"], 15)  # dwell_s, then closed
    r = http.get("/navigation/elevator_open_door", params={"open": 1})
    assert r.status_code == 200 and r.json() == {"status": "ok"}, r.text
    assert wait_for(lambda: info(http)["front_door_open"], 15)
    r = http.get("/navigation/elevator_open_door", params={"elevator_name": "lift1", "open": 0})
    assert r.json() == {"status": "ok"}
    assert wait_for(lambda: not info(http)["front_door_open"], 15)


def test_bad_input_is_refused_with_a_reason(http: httpx.Client,
                                            controller: ElevatorNode) -> None:
    r = http.get("/navigation/elevator_to_level", params={"level": 7})
    assert r.status_code == 400
    assert r.json() == {"result": False,
                        "description": "lift1 does not serve level 7 (levels 1, 2, 3)"}
    for op, query in OPS:
        r = http.get(op, params={**query, "elevator_name": "lift9"})
        assert r.status_code == 404, (op, r.text)
        assert "unknown elevator 'lift9' (elevators: lift1)" in r.text
    for query in ({"level": "two"}, {}, {"level": 2, "x": 1}):
        r = http.get("/navigation/elevator_to_level", params=query)
        assert r.status_code == 400, (query, r.text)
        assert r.json()["result"] is False
    for query in ({"open": 2}, {"open": "yes"}, {}):
        r = http.get("/navigation/elevator_open_door", params=query)
        assert r.status_code == 400, (query, r.text)
        assert r.json()["status"] == "error"
