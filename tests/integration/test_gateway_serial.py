"""docs/robot-api.md §13 serial bridge on a pseudo-terminal pair (the test plays the outside
controller with pyserial) and the §1.3 discovery broadcast on a loopback UDP socket."""

from __future__ import annotations

import json
import socket
import struct
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
import serial
from zenros.context import Context
from zenros.msgs.zenros_msgs import NavStatus
from zenros.qos import QOS_LATCHED
from zenros.services.gateway.serial.frame import HEADER, STATUS_FRAME_LEN, command_frame
from zenros.services.gateway.testing import NullModem, running_gateway
from zenros.testing import wait_for


class RecordingNav:
    """A NavPort that records what it is asked (stands in for the nav service here)."""

    def __init__(self) -> None:
        self.calls: list[tuple[str, tuple[object, ...]]] = []

    def __getattr__(self, name: str) -> object:
        async def record(*args: object) -> None:
            self.calls.append((name, args))
        return record


@pytest.fixture
def modem() -> Iterator[NullModem]:
    m = NullModem()
    yield m
    m.close()


def read_frame(port: serial.Serial) -> bytes:
    buf = b""
    while True:
        buf += port.read(STATUS_FRAME_LEN)
        i = buf.find(HEADER)
        if i >= 0 and len(buf) - i >= STATUS_FRAME_LEN:
            return buf[i:i + STATUS_FRAME_LEN]


def test_status_out_commands_in(ctx_pair: list[Context], tmp_path: Path,
                                modem: NullModem) -> None:
    with running_gateway(ctx_pair[0], tmp_path, serial_port=modem.a) as gw, \
            serial.Serial(modem.b, 115200, timeout=2) as ctl:
        nav = RecordingNav()
        gw.core.nav = nav  # type: ignore[assignment]
        gw.core.state.voltage = 37.05
        for _ in range(300):  # frames queued in the pty before the voltage was set come first
            frame = read_frame(ctl)
            assert len(frame) == 89 and frame[3] == 0x55 and frame[-1] == 0
            fields = struct.unpack("<7if2if i4fI3fi", frame[4:-1])
            if abs(fields[7] - 37.05) < 1e-5:
                break
        assert fields[7] == pytest.approx(37.05, abs=1e-5)
        counter = fields[16]
        assert struct.unpack("<7if2if i4fI3fi", read_frame(ctl)[4:-1])[16] > counter
        # garbage, an oversize packet, then 'g' 3 split over two writes
        ctl.write(b"\x00\xffjunk" + HEADER + b"\x30" + b"x" * 10)
        ctl.write(command_frame(b"g\x03")[:3])
        ctl.write(command_frame(b"g\x03")[3:])
        assert wait_for(lambda: ("goto_index", (3,)) in nav.calls, 5), nav.calls
        ctl.write(command_frame(b"i\x02"))
        assert wait_for(lambda: ("cancel", ()) in nav.calls, 5)
        assert gw.serial is not None and gw.serial.parser.rejected >= 1


def test_missing_port_never_blocks(ctx_pair: list[Context], tmp_path: Path,
                                   caplog: pytest.LogCaptureFixture) -> None:
    with running_gateway(ctx_pair[0], tmp_path, serial_port=str(tmp_path / "ttyNONE")) as gw:
        assert gw.serial is not None and not gw.serial.connected.is_set()
        assert wait_for(lambda: "retrying" in caplog.text, 5)
        assert gw.core.status.header.seq >= 0  # the gateway runs on


def test_discovery_broadcast_on_loopback(ctx_pair: list[Context], tmp_path: Path) -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as rx:
        rx.bind(("127.0.0.1", 0))
        rx.settimeout(5)
        port = rx.getsockname()[1]
        with running_gateway(ctx_pair[0], tmp_path, discovery_port=port,
                             discovery_address="127.0.0.1", discovery_period=0.1) as gw:
            first = json.loads(rx.recv(1024))
            second = json.loads(rx.recv(1024))
            assert first == second
            assert set(first) == {"id", "port", "mac", "version"}
            assert first["port"] == gw.rest_port and len(first["mac"]) == 17
            assert all(c in "0123456789ABCDEF" for c in first["id"])


def test_m_04_stops_navigation_and_it_stays_stopped(
        ctx_pair: list[Context], tmp_path: Path, modem: NullModem, make_node: Any) -> None:
    """``m 04`` brings navStatus to 0 and nav's next status updates do not undo it (issue 21
    item 9: nav_status was still 1 30 s later); ``m 00`` opens navigation again."""
    nav_side = make_node("fake_nav", 1)
    status = nav_side.create_publisher(NavStatus, "nav/status", QOS_LATCHED)

    def update(distance: float) -> Callable[[], bool]:
        status.publish(NavStatus(state="idle", target_distance=distance))
        return lambda: gw.core.state.goal.distance == distance

    with running_gateway(ctx_pair[0], tmp_path, serial_port=modem.a) as gw, \
            serial.Serial(modem.b, 115200, timeout=2) as ctl:
        assert wait_for(update(1.5), 5) and gw.core.refresh().navStatus == 1
        ctl.write(command_frame(b"m\x04"))
        assert wait_for(lambda: gw.nav_actions.stopped, 5)
        assert wait_for(update(2.5), 5)  # nav's status update arrived after the stop
        assert gw.core.refresh().navStatus == 0
        assert wait_for(lambda: nav_status_of(read_frame(ctl)) == 0, 5)
        ctl.write(command_frame(b"m\x00"))
        assert wait_for(lambda: not gw.nav_actions.stopped, 5)
        assert wait_for(update(3.5), 5) and gw.core.refresh().navStatus == 1


def nav_status_of(frame: bytes) -> int:
    return int(struct.unpack("<7if2if i4fI3fi", frame[4:-1])[0])
