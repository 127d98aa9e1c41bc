"""docs/robot-api.md §13 serial frames: the 89-byte status packet out, command packets in (with
resync)."""

from __future__ import annotations

import struct

from zenros.msgs.galileo_msgs import GalileoStatus

from ..state.status import f32

__all__ = ["HEADER", "MAX_CMD_LEN", "STATUS_FRAME_LEN", "CommandParser", "command_frame",
           "status_frame"]

HEADER = b"\xcd\xeb\xd7"
MAX_CMD_LEN = 20
_STATUS = struct.Struct("<7if2if i4fI3fi")
STATUS_FRAME_LEN = len(HEADER) + 1 + _STATUS.size + 1  # 89


def status_frame(st: GalileoStatus, counter: int) -> bytes:
    """The status packet: header, LEN=0x55, 21 little-endian fields, 0x00."""
    payload = _STATUS.pack(
        st.navStatus, st.visualStatus, st.mapStatus, st.gcStatus, st.gbaStatus,
        st.chargeStatus, st.loopStatus, f32(st.power), st.targetNumID, st.targetStatus,
        f32(st.targetDistance), st.angleGoalStatus, f32(st.controlSpeedX),
        f32(st.controlSpeedTheta), f32(st.currentSpeedX), f32(st.currentSpeedTheta),
        counter & 0xFFFFFFFF, f32(st.currentPosX), f32(st.currentPosY), f32(st.currentAngle),
        st.busyStatus)
    return HEADER + bytes([len(payload) + 1]) + payload + b"\x00"


def command_frame(data: bytes) -> bytes:
    """A host → robot command packet (for tests and tools)."""
    return HEADER + bytes([len(data)]) + data


class CommandParser:
    """Feeds bytes in, yields complete command payloads.

    Garbage before a header is skipped; a packet announcing ``LEN > 20`` (or 0) is
    ignored and the search for the next header restarts right after its header.
    """

    def __init__(self) -> None:
        self._buf = bytearray()
        self.skipped = 0
        self.rejected = 0

    def feed(self, data: bytes) -> list[bytes]:
        buf = self._buf
        buf += data
        out: list[bytes] = []
        while True:
            i = buf.find(HEADER)
            if i < 0:
                keep = min(2, len(buf))  # a header may straddle reads
                self.skipped += len(buf) - keep
                del buf[:len(buf) - keep]
                return out
            if i:
                self.skipped += i
                del buf[:i]
            if len(buf) < 4:
                return out
            n = buf[3]
            if n == 0 or n > MAX_CMD_LEN:
                self.rejected += 1
                del buf[:3]
                continue
            if len(buf) < 4 + n:
                return out
            out.append(bytes(buf[4:4 + n]))
            del buf[:4 + n]
