"""docs/robot-api.md §14 register tables without a network: encoding, holding-register writes,
refusals."""

from __future__ import annotations

import math

import pytest
from pymodbus.client import ModbusTcpClient
from zenros.msgs.galileo_msgs import GalileoStatus
from zenros.services.gateway.modbus.tables import (
    DI_COUNT,
    IR_COUNT,
    decode_f32,
    discrete_inputs,
    encode_f32,
    input_registers,
    parse_holding_write,
)

DT = ModbusTcpClient.DATATYPE


def test_spec_example_voltage() -> None:
    assert encode_f32(37.05) == [13107, 16916]
    regs = input_registers(GalileoStatus(power=37.05))
    assert regs[1:3] == [13107, 16916]


@pytest.mark.parametrize("v", [0.0, -1.0, 1.5, 1e-3, -123.25])
def test_float_words_match_pymodbus_little_word_order(v: float) -> None:
    assert encode_f32(v) == ModbusTcpClient.convert_to_registers(v, DT.FLOAT32,
                                                                  word_order="little")
    assert decode_f32(encode_f32(v)) == pytest.approx(v, rel=1e-6)


def test_table_layout() -> None:
    st = GalileoStatus(visualStatus=-1, targetNumID=-2, targetStatus=1, chargeStatus=4,
                       currentPosX=1.25, currentAngle=-0.5, navStatus=1, loopStatus=1)
    st.header.seq, st.header.stamp.secs = 70000, 1_700_000_000
    regs = input_registers(st)
    assert len(regs) == IR_COUNT
    assert regs[0] == 0xFFFF and regs[3] == 0xFFFE and regs[4] == 1 and regs[21] == 4
    assert decode_f32(regs[15:17]) == 1.25 and decode_f32(regs[19:21]) == -0.5
    assert regs[23] + (regs[24] << 16) == 1_700_000_000
    assert regs[25] + (regs[26] << 16) == 70000
    bits = discrete_inputs(st)
    assert len(bits) == DI_COUNT and bits[:6] == [True, False, False, False, True, False]


def test_speed_write_combines_with_current_registers() -> None:
    current = [0] * 14
    cmd = parse_holding_write(current, 0, encode_f32(0.5), max_speed=1.0)
    assert cmd.speed == (0.5, 0.0)
    current[2:4] = encode_f32(-0.25)
    cmd = parse_holding_write(current, 0, encode_f32(0.5), max_speed=1.0)
    assert cmd.speed == (0.5, -0.25) and cmd.goal is None and cmd.nav_index is None


def test_goal_needs_all_six_registers_or_the_control_word() -> None:
    current = [0] * 14
    regs = encode_f32(1.0) + encode_f32(2.0) + encode_f32(0.5)
    cmd = parse_holding_write(current, 7, regs, max_speed=1.0)
    assert cmd.goal == (1.0, 2.0, 0.5)
    assert parse_holding_write(current, 7, regs[:2], max_speed=1.0).goal is None
    current[7:13] = regs
    assert parse_holding_write(current, 13, [1], max_speed=1.0).goal == (1.0, 2.0, 0.5)


@pytest.mark.parametrize("address, values, word", [
    (0, encode_f32(2.0), "speed out of range"),
    (0, encode_f32(math.nan), "non-finite"),
    (2, encode_f32(math.inf), "non-finite"),
    (4, [256], "out of range"),
    (4, [0xFFFE], "out of range"),
    (5, [3], "control code"),
    (6, [2], "charge code"),
    (13, [5], "goal control word"),
    (7, encode_f32(math.nan) + encode_f32(0) + encode_f32(0), "non-finite"),
])
def test_refusals(address: int, values: list[int], word: str) -> None:
    with pytest.raises(ValueError, match=word):
        parse_holding_write([0] * 14, address, values, max_speed=1.0)


def test_index_minus_one_cancels() -> None:
    assert parse_holding_write([0] * 14, 4, [0xFFFF], max_speed=1.0).nav_index == -1


def test_values_beyond_float32_saturate_to_infinity() -> None:
    # a client's /cmd_vel of 1e308 reaches controlSpeedX; the table must still build
    assert decode_f32(encode_f32(1e308)) == math.inf
    assert decode_f32(encode_f32(-1e308)) == -math.inf
    regs = input_registers(GalileoStatus(controlSpeedX=1e308, controlSpeedTheta=-1e300))
    assert len(regs) == IR_COUNT
