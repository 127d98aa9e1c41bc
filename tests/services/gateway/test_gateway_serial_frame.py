"""docs/robot-api.md §13 frames without a port: the status packet layout and the command parser's
resync."""

from __future__ import annotations

import struct

import pytest
from zenros.msgs.galileo_msgs import GalileoStatus
from zenros.services.gateway.serial.frame import (
    HEADER,
    STATUS_FRAME_LEN,
    CommandParser,
    command_frame,
    status_frame,
)


def test_status_frame_layout() -> None:
    st = GalileoStatus(navStatus=1, visualStatus=2, chargeStatus=3, power=37.05,
                       targetNumID=-2, targetDistance=1.5, currentPosX=-3.0, busyStatus=1)
    f = status_frame(st, 12345)
    assert STATUS_FRAME_LEN == 89 and len(f) == 89
    assert f[:3] == HEADER and f[3] == 0x55 and f[-1] == 0
    fields = struct.unpack("<7if2if i4fI3fi", f[4:-1])
    assert fields[0] == 1 and fields[1] == 2 and fields[5] == 3
    assert fields[7] == pytest.approx(37.05) and fields[8] == -2
    assert fields[10] == 1.5 and fields[16] == 12345 and fields[17] == -3.0
    assert fields[20] == 1
    assert struct.unpack("<I", status_frame(st, 2**32 + 7)[4 + 64:4 + 68])[0] == 7


def test_parser_splits_and_resyncs() -> None:
    p = CommandParser()
    data = b"noise" + command_frame(b"m\x00") + b"\xcd\xeb" + command_frame(b"g\x05")
    out = []
    for b in data:  # one byte at a time, as a slow line delivers them
        out += p.feed(bytes([b]))
    assert out == [b"m\x00", b"g\x05"]
    assert p.skipped >= 5


def test_parser_ignores_len_over_20_and_zero() -> None:
    p = CommandParser()
    assert p.feed(HEADER + b"\x15" + b"x" * 21 + command_frame(b"i\x01")) == [b"i\x01"]
    assert p.feed(HEADER + b"\x00" + command_frame(b"j\x00")) == [b"j\x00"]
    assert p.rejected == 2


def test_parser_waits_for_the_whole_packet() -> None:
    p = CommandParser()
    assert p.feed(HEADER + b"\x03ab") == []
    assert p.feed(b"c") == [b"abc"]
    assert p.feed(b"\xcd") == [] and p.feed(b"\xeb\xd7\x01z") == [b"z"]


def test_status_frame_with_values_beyond_float32() -> None:
    # a client's /cmd_vel of 1e308 reaches controlSpeedX; the packet must still be built
    frame = status_frame(GalileoStatus(controlSpeedX=1e308, controlSpeedTheta=-1e300), 1)
    assert len(frame) == STATUS_FRAME_LEN
