"""zenros's CDR codec on its own: round trips, malformed input (always `DecodeError`, never a
crash), encode errors and both byte orders (speed: bench/ros2_cdr.py)."""

from __future__ import annotations

import random
import struct

import numpy as np
import pytest
from zenros.action.types import UUID
from zenros.codec import from_builtins
from zenros.errors import DecodeError, EncodeError
from zenros.msgs.geometry_msgs import PoseWithCovariance, Twist, Vector3
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry
from zenros.msgs.sensor_msgs import JointState, LaserScan
from zenros.msgs.std_msgs import Header, String, UInt8
from zenros.msgs.zenros_msgs import ChassisState
from zenros.ros2 import cdr_codec, ros_name_of
from zenros.ros2.cdr import cdr_codec_for_name
from zenros.ros2.registry import derive_definition

from rosref import values_of

TYPES = [String, Twist, Odometry, LaserScan, JointState, OccupancyGrid, Header]


def _sample(cls: type) -> object:
    name = ros_name_of(cls)
    return from_builtins(values_of(name, random.Random(name)), cls)


@pytest.mark.parametrize("cls", TYPES, ids=lambda c: c.__name__)
def test_round_trip(cls: type) -> None:
    codec = cdr_codec(cls)
    msg = _sample(cls)
    data = codec.encode(msg)
    assert data[:4] == b"\x00\x01\x00\x00"
    assert codec.decode(data) == msg
    assert codec.decode(memoryview(data)) == msg
    assert codec.decode(bytearray(data)) == msg


@pytest.mark.parametrize("cls", TYPES, ids=lambda c: c.__name__)
def test_every_truncation_is_a_decode_error(cls: type) -> None:
    codec = cdr_codec(cls)
    data = codec.encode(_sample(cls))
    for n in range(len(data)):
        with pytest.raises(DecodeError):
            codec.decode(data[:n])


@pytest.mark.parametrize("cls", TYPES, ids=lambda c: c.__name__)
def test_corrupted_bytes_decode_or_raise_decode_error(cls: type) -> None:
    codec = cdr_codec(cls)
    data = codec.encode(_sample(cls))
    rnd = random.Random(7)
    for _ in range(300):
        b = bytearray(data)
        for _ in range(rnd.randint(1, 4)):
            b[rnd.randrange(4, len(b))] = rnd.randrange(256)
        try:
            codec.decode(bytes(b))
        except DecodeError:
            pass


def test_hostile_counts_fail_fast() -> None:
    # a sequence claiming 4 billion elements, a string claiming 4 GB
    for cls in (JointState, LaserScan, String):
        codec = cdr_codec(cls)
        msg = codec.encode(cls())
        for off in range(4, len(msg) - 3, 4):
            data = bytearray(msg)
            data[off:off + 4] = b"\xff\xff\xff\xff"
            try:
                codec.decode(bytes(data))
            except DecodeError as exc:
                assert "expected" in str(exc)


@pytest.mark.parametrize("head", [b"", b"\x00", b"\x00\x07\x00\x00",
                                  b"\x01\x01\x00\x00", b"\x00\x02\x00\x00"])
def test_bad_headers(head: bytes) -> None:
    with pytest.raises(DecodeError, match="std_msgs/msg/String"):
        cdr_codec(String).decode(head + b"\x01\x00\x00\x00\x00")


def test_big_endian_payloads_are_read() -> None:
    be = b"\x00\x00\x00\x00" + struct.pack(">I", 3) + b"hi\x00"
    assert cdr_codec(String).decode(be) == String(data="hi")
    scan = LaserScan(angle_min=-1.5, ranges=np.array([1.0, 2.5], dtype=np.float32))
    le = cdr_codec(LaserScan).encode(scan)
    # LaserScan: stamp(2 x 4) + frame_id(4 + 1) + pad(3) + 7 float32 + n + 2 float32 + n
    be = (b"\x00\x00\x00\x00" + struct.pack(">iI", 0, 0) + struct.pack(">I", 1) + b"\x00"
          + b"\x00" * 3 + struct.pack(">7f", -1.5, 0, 0, 0, 0, 0, 0)
          + struct.pack(">I2f", 2, 1.0, 2.5) + struct.pack(">I", 0))
    assert len(be) == len(le)
    got = cdr_codec(LaserScan).decode(be)
    assert got == scan and got.ranges.dtype == np.float32


def test_encode_errors_are_clear() -> None:
    with pytest.raises(EncodeError, match="std_msgs/msg/UInt8"):
        cdr_codec(UInt8).encode(UInt8(data=256))
    with pytest.raises(EncodeError, match="covariance.*36"):
        cdr_codec(PoseWithCovariance).encode(PoseWithCovariance(covariance=np.zeros(5)))
    with pytest.raises(EncodeError):
        cdr_codec(Twist).encode(Twist(linear="fast"))  # type: ignore[arg-type]


def test_numpy_fields_decode_as_views_of_the_payload() -> None:
    grid = OccupancyGrid(data=np.arange(-50, 50, dtype=np.int8))
    data = cdr_codec(OccupancyGrid).encode(grid)
    got = cdr_codec(OccupancyGrid).decode(data)
    assert got == grid and got.data.base is not None


def test_zenros_only_types_get_a_derived_definition() -> None:
    d = derive_definition(ChassisState)
    assert d.name == "zenros_msgs/msg/ChassisState"
    codec = cdr_codec(ChassisState)
    msg = ChassisState()
    assert codec.decode(codec.encode(msg)) == msg


def test_plain_classes_for_action_parts() -> None:
    codec = cdr_codec_for_name("example_interfaces/action/Fibonacci_SendGoal_Request")
    # zenros's own UUID class (zenros.action.types, imported above so the test does not depend
    # on what other tests imported first) holds the 16 bytes as a list of numbers, as ROS does
    assert cdr_codec_for_name("unique_identifier_msgs/msg/UUID").type is UUID
    msg = codec.type(goal_id=UUID(uuid=list(range(16))))  # type: ignore[call-arg]
    data = codec.encode(msg)
    assert data == b"\x00\x01\x00\x00" + bytes(range(16)) + b"\x00\x00\x00\x00"
    assert codec.decode(data) == msg
