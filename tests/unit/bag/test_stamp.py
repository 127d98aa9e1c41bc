"""Publish times read from a payload's header without decoding the whole message."""

from __future__ import annotations

from zenros.bag.stamp import stamp_reader
from zenros.codec import codec_for
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.std_msgs import Header


def test_json_header_stamp() -> None:
    read = stamp_reader("nav_msgs/Odometry", False)
    assert read is not None
    data = codec_for(Odometry).encode(Odometry(header=Header(stamp=Time(sec=12, nanosec=34))))
    assert read(data) == 12_000_000_034


def test_msgpack_header_stamp() -> None:
    read = stamp_reader("sensor_msgs/LaserScan", True)
    assert read is not None
    data = codec_for(LaserScan).encode(LaserScan(header=Header(stamp=Time(sec=5))))
    assert read(data) == 5_000_000_000


def test_types_without_header_and_bad_payloads() -> None:
    assert stamp_reader("geometry_msgs/Twist", False) is None
    assert stamp_reader("no_pkg/Unknown", False) is None
    read = stamp_reader("nav_msgs/Odometry", False)
    assert read is not None
    assert read(b"not json") == 0
    assert read(b'{"header": {"stamp": {"sec": "x"}}}') == 0
    assert read(b"{}") == 0
