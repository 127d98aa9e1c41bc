"""The docs/robot-api.md §14 Modbus tables: GalileoStatus → discrete inputs and input registers;
holding register writes → commands. 1-based in the spec, 0-based here (pymodbus addresses).

32-bit values are big-byte little-word ("CDAB"): the low 16-bit word comes first.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Sequence
from dataclasses import dataclass

from zenros.msgs.galileo_msgs import GalileoStatus

from ..state.status import f32

__all__ = [
    "COIL_COUNT", "DI_COUNT", "HR_COUNT", "IR_COUNT", "HoldingWrite", "decode_f32",
    "discrete_inputs", "encode_f32", "input_registers", "parse_holding_write",
]

DI_COUNT = 38     # doc 1-6 status bits, 7-22 input IO 0-15, 23-30 output IO 0-7,
#                   31-38 the ASR board's IO 0-7 (ours: the spec's table ends at 30)
COIL_COUNT = 4    # doc 1-4: the ASR board's outputs 0-3 (ours: §14 has no coils)
IR_COUNT = 27     # doc 1..27 (the uint32 at doc 26 ends at 27)
HR_COUNT = 14     # doc 1..14


def encode_f32(v: float) -> list[int]:
    """float32 → two registers, low word first."""
    hi, lo = struct.unpack(">HH", struct.pack(">f", f32(v)))
    return [lo, hi]


def decode_f32(regs: list[int]) -> float:
    lo, hi = regs
    value: float = struct.unpack(">f", struct.pack(">HH", hi, lo))[0]
    return value


def _u32(v: int) -> list[int]:
    v &= 0xFFFFFFFF
    return [v & 0xFFFF, v >> 16]


def _i16(v: int) -> int:
    return max(-32768, min(32767, int(v))) & 0xFFFF


def discrete_inputs(st: GalileoStatus, ext_inputs: Sequence[int] = (),
                    ext_outputs: Sequence[int] = (), asr_io: Sequence[bool] = ()) -> list[bool]:
    """Doc addresses 1-38: six status bits, the extension IO board's inputs 0-15 (7-22)
    and outputs 0-7 (23-30), the ASR board's IO 0-7 (31-38); IO bits the chassis has not
    reported read 0."""
    bits = [st.navStatus == 1, st.mapStatus == 1, st.gcStatus == 1, st.gbaStatus == 1,
            st.loopStatus == 1, st.busyStatus == 1]
    bits += [bool(v) for v in list(ext_inputs)[:16]] + [False] * (16 - min(16, len(ext_inputs)))
    bits += [bool(v) for v in list(ext_outputs)[:8]] + [False] * (8 - min(8, len(ext_outputs)))
    bits += [bool(v) for v in list(asr_io)[:8]] + [False] * (8 - min(8, len(asr_io)))
    return bits + [False] * (DI_COUNT - len(bits))


def input_registers(st: GalileoStatus) -> list[int]:
    """Doc addresses 1-27 as 16-bit register values (doc 23 is unused and reads 0)."""
    r = [_i16(st.visualStatus)]
    r += encode_f32(st.power)
    r += [_i16(st.targetNumID), _i16(st.targetStatus)]
    for v in (st.targetDistance, st.controlSpeedX, st.controlSpeedTheta, st.currentSpeedX,
              st.currentSpeedTheta, st.currentPosX, st.currentPosY, st.currentAngle):
        r += encode_f32(v)
    r += [_i16(st.chargeStatus), 0]
    r += _u32(st.header.stamp.secs) + _u32(st.header.seq)
    assert len(r) == IR_COUNT
    return r


@dataclass(frozen=True)
class HoldingWrite:
    """What a holding-register write asks for (None: not part of this write)."""

    speed: tuple[float, float] | None = None        # linear m/s, angular rad/s
    nav_index: int | None = None                    # -1 cancel, else nav point
    control: int | None = None                      # 0 cancel, 1 pause, 2 resume
    charge: int | None = None                       # 1 go charge, 0 stop charge
    goal: tuple[float, float, float] | None = None  # x, y, theta (map)


def _signed(v: int) -> int:
    return v - 0x10000 if v & 0x8000 else v


def parse_holding_write(current: list[int], address: int, values: list[int],
                        max_speed: float) -> HoldingWrite:
    """Interpret a write of ``values`` at 0-based ``address`` over ``current`` registers.

    Raises:
        ValueError: a value the robot cannot take (non-finite or too fast a speed, an
            index out of range, an unknown control code).
    """
    regs = list(current[:HR_COUNT]) + [0] * max(0, HR_COUNT - len(current))
    touched = range(address, address + len(values))
    regs[address:address + len(values)] = values
    out: dict[str, object] = {}
    if any(a in touched for a in range(4)):
        lin, ang = decode_f32(regs[0:2]), decode_f32(regs[2:4])
        if not (math.isfinite(lin) and math.isfinite(ang)):
            raise ValueError("speed registers hold a non-finite float")
        if abs(lin) > max_speed or abs(ang) > 6.3:
            raise ValueError(f"speed out of range: {lin:.3g} m/s, {ang:.3g} rad/s")
        out["speed"] = (lin, ang)
    if 4 in touched:
        idx = _signed(regs[4])
        if not -1 <= idx <= 255:
            raise ValueError(f"nav point index {idx} out of range (-1..255)")
        out["nav_index"] = idx
    if 5 in touched:
        if regs[5] not in (0, 1, 2):
            raise ValueError(f"control code {regs[5]} (0 cancel, 1 pause, 2 resume)")
        out["control"] = regs[5]
    if 6 in touched:
        if regs[6] not in (0, 1):
            raise ValueError(f"charge code {regs[6]} (1 go charge, 0 stop)")
        out["charge"] = regs[6]
    whole_goal = address <= 7 and address + len(values) >= 13
    if whole_goal or (13 in touched and regs[13] == 1):
        x, y, th = decode_f32(regs[7:9]), decode_f32(regs[9:11]), decode_f32(regs[11:13])
        if not all(math.isfinite(v) and abs(v) < 1e5 for v in (x, y, th)):
            raise ValueError("goal registers hold a non-finite or huge float")
        out["goal"] = (x, y, th)
    elif 13 in touched and regs[13] not in (0, 1):
        raise ValueError(f"goal control word {regs[13]} (1 = go)")
    return HoldingWrite(**out)  # type: ignore[arg-type]
