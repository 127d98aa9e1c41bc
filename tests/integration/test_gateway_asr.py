"""docs/robot-api.md §3.8's ASR board through a real server and the simulated chassis's board:
IO outputs set and read back (REST, and on the chassis's latched asr/state), PWM and a servo
turning to its angle, refusals with the reason, and 503 without a board; its IO on Modbus
(pymodbus' client: coils 1-4 its outputs, discrete inputs 31-38 its ports)."""

from __future__ import annotations

from collections.abc import Iterator

import httpx
import pytest
from zenros.context import Context
from zenros.msgs.zenros_msgs import AsrBoardState
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.testing import wait_for


@pytest.fixture
def chassis(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_rate": 0.0, "actuators": False, "speed": 5.0})
    yield node
    node.close()


def test_no_board_is_a_503(gw: GatewayNode, http: httpx.Client) -> None:
    r = http.get("/system/asr/io")
    assert r.status_code == 503 and "no ASR board" in r.json()["description"], r.text
    r = http.put("/system/asr/io", json={"0": True})
    assert r.status_code == 503 and "asr/set is not in the graph" in r.json()["description"]


def test_outputs_pwm_and_servo(chassis: ChassisNode, gw: GatewayNode, http: httpx.Client,
                               ctx_pair: list[Context]) -> None:
    assert wait_for(lambda: http.get("/system/asr/io").status_code == 200, 20)
    assert http.get("/system/asr/io").json() == {str(i): False for i in range(8)}
    heard: list[AsrBoardState] = []
    user = Node("asr_listener", context=ctx_pair[0])
    try:
        user.create_subscription(AsrBoardState, "asr/state", heard.append, QOS_LATCHED)
        r = http.put("/system/asr/io", json={"0": True, "2": True})
        assert r.status_code == 200 and r.json() == {"status": "ok"}, r.text
        assert http.get("/system/asr/io").json() == {
            "0": True, "1": False, "2": True, "3": False, "4": False, "5": False, "6": False,
            "7": False}
        assert wait_for(lambda: bool(heard) and heard[-1].io[:4] == [True, False, True, False],
                        10)  # on ROS too
        assert wait_for(lambda: http.get("/system/asr/pwm", params={
            "port": 1, "freq": 2000, "percent": 40}).status_code == 200, 5)  # 100 updates/s
        assert wait_for(lambda: heard[-1].pwm_freq[1] == 2000
                        and heard[-1].pwm_percent[1] == 40, 10)
        assert wait_for(lambda: http.get("/system/asr/servo", params={
            "port": 3, "angle": 0}).status_code == 200, 5)
        assert wait_for(lambda: heard[-1].servo_angle[3] == 0.0, 20), heard[-1]
    finally:
        user.close()
    for method, path, kw, words in (
            ("PUT", "/system/asr/io", {"json": {"5": True}}, "port 5 is an input"),
            ("PUT", "/system/asr/io", {"json": {"1": "yes"}}, "Expected `bool`"),
            ("PUT", "/system/asr/io", {"json": {}}, "length"),
            ("GET", "/system/asr/pwm", {"params": {"port": 4, "freq": 1, "percent": 1}},
             "port"),
            ("GET", "/system/asr/pwm", {"params": {"port": 0, "freq": 1, "percent": 101}},
             "percent"),
            ("GET", "/system/asr/servo", {"params": {"port": 0, "angle": 200}}, "angle"),
            ("GET", "/system/asr/servo", {"params": {"port": 0}}, "angle")):
        r = http.request(method, path, **kw)
        assert r.status_code == 400 and words in r.json()["description"], (path, kw, r.text)
    assert http.get("/system/asr/io").json()["0"] is True  # nothing lost


def test_the_boards_io_on_modbus(chassis: ChassisNode, gw: GatewayNode,
                                 http: httpx.Client) -> None:
    from pymodbus.client import ModbusTcpClient

    assert wait_for(lambda: http.get("/system/asr/io").status_code == 200, 20)
    with ModbusTcpClient("127.0.0.1", port=gw.modbus_port) as c:
        assert c.read_coils(0, count=4, device_id=1).bits[:4] == [False] * 4
        assert not c.write_coil(1, True, device_id=1).isError()
        assert http.get("/system/asr/io").json()["1"] is True
        # the board takes 100 updates a second: a write right after is refused, then taken
        assert wait_for(lambda: not c.write_coils(2, [True, True], device_id=1).isError(), 5)
        assert wait_for(lambda: c.read_coils(0, count=4, device_id=1).bits[:4]
                        == [False, True, True, True], 5)
        assert wait_for(lambda: c.read_discrete_inputs(30, count=8, device_id=1).bits[:8]
                        == [False, True, True, True, False, False, False, False], 5)
        bad = c.write_coils(3, [True, True], device_id=1)  # coil 5 is past the table
        assert bad.isError() and bad.exception_code == 2
        bad = c.read_coils(4, count=1, device_id=1)
        assert bad.isError() and bad.exception_code == 2
        assert c.read_coils(0, count=5, device_id=1).bits[4] is False  # past coil 4: 0
    assert http.get("/system/asr/io").json()["3"] is True
