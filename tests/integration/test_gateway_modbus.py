"""docs/robot-api.md §14 Modbus TCP through pymodbus' own client against the running gateway."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from pymodbus.client import AsyncModbusTcpClient, ModbusTcpClient
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway
from zenros.testing import Collector, wait_for

DT = ModbusTcpClient.DATATYPE


@pytest.fixture
def gw(ctx_pair: list[Context], tmp_path: Path) -> Iterator[GatewayNode]:
    with running_gateway(ctx_pair[0], tmp_path) as node:
        yield node


async def test_spec_example_and_status_tables(gw: GatewayNode) -> None:
    s = gw.core.state
    s.voltage, s.nav_open, s.busy, s.pose, s.pose_time = 37.05, True, True, (1.5, -2.0, 0.5), 1e12
    s.speed_x = 0.25
    gw.core.refresh()
    c = AsyncModbusTcpClient("127.0.0.1", port=gw.modbus_port)
    await c.connect()
    try:
        rr = await c.read_input_registers(1, count=2, device_id=1)  # doc address 2 (§14.4)
        assert rr.registers == [13107, 16916]
        v = c.convert_from_registers(rr.registers, DT.FLOAT32, word_order="little")
        assert v == pytest.approx(37.05, abs=1e-5)
        rr = await c.read_input_registers(0, count=27, device_id=1)
        regs = rr.registers
        assert regs[0] == 1                                   # visualStatus tracking
        assert regs[3] == 0xFFFF                              # targetNumID -1
        def f(doc: int) -> float:
            return float(c.convert_from_registers(regs[doc - 1:doc + 1], DT.FLOAT32,
                                                  word_order="little"))
        assert f(12) == 0.25 and f(16) == 1.5 and f(18) == -2.0 and f(20) == 0.5
        di = await c.read_discrete_inputs(0, count=6, device_id=1)
        assert di.bits[:6] == [True, False, False, False, False, True]  # nav, busy
        bad = await c.read_input_registers(40, count=2, device_id=1)
        assert bad.isError() and bad.exception_code == 2           # ILLEGAL ADDRESS
        bad = await c.read_input_registers(20, count=10, device_id=1)  # runs past doc 27
        assert bad.isError() and bad.exception_code == 2
        bad = await c.read_coils(4, count=1, device_id=1)  # coils 1-4: the ASR board's
        assert bad.isError() and bad.exception_code == 2
        bad = await c.write_register(20, 1, device_id=1)           # past holding reg 14
        assert bad.isError() and bad.exception_code == 2
    finally:
        c.close()


async def test_speed_write_goes_through_deadman(gw: GatewayNode, make_node: object) -> None:
    base = make_node("fake_base", 1)  # type: ignore[operator]
    got: Collector[Twist] = Collector()
    base.create_subscription(Twist, "cmd_vel", got, 50)
    assert gw.topics.cmd_vel_pub.wait_for_subscribers(1, 5)
    c = AsyncModbusTcpClient("127.0.0.1", port=gw.modbus_port)
    await c.connect()
    try:
        regs = (c.convert_to_registers(0.3, DT.FLOAT32, word_order="little")
                + c.convert_to_registers(-0.4, DT.FLOAT32, word_order="little"))
        rr = await c.write_registers(0, regs, device_id=1)
        assert not rr.isError()
        assert wait_for(lambda: any(abs(t.linear.x - 0.3) < 1e-6 and abs(t.angular.z + 0.4)
                                    < 1e-6 for t in got.items), 3)
        assert wait_for(lambda: got.items[-1].linear.x == 0.0, 3)   # dead-man stop
        # out of range, NaN, bad codes: ILLEGAL VALUE, nothing published
        n = len(got.items)
        for addr, values in [(0, c.convert_to_registers(9.0, DT.FLOAT32, word_order="little")),
                             (0, [0, 0x7FC0]), (4, [300]), (5, [7]), (6, [5]), (13, [9])]:
            rr = await c.write_registers(addr, values, device_id=1)
            assert rr.isError() and rr.exception_code == 3, (addr, values)
        assert len(got.items) == n
        # navigation commands without a nav service: DEVICE FAILURE, server still fine
        rr = await c.write_register(4, 2, device_id=1)
        assert rr.isError() and rr.exception_code == 4
        rr = await c.read_input_registers(1, count=2, device_id=1)
        assert not rr.isError()
    finally:
        c.close()


def test_sync_client_reads(gw: GatewayNode) -> None:
    gw.core.state.voltage = 24.0
    gw.core.refresh()
    with ModbusTcpClient("127.0.0.1", port=gw.modbus_port) as c:
        rr = c.read_input_registers(1, count=2, device_id=1)
        assert c.convert_from_registers(rr.registers, DT.FLOAT32, word_order="little") == 24.0
