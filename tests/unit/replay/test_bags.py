"""OutputBag, InputDecoder and compare_bags: deterministic files, read back, first difference."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from zenros.bag.reader import bag_files, iter_messages
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.sensor_msgs import LaserScan
from zenros.replay.compare import compare_bags, first_field_difference
from zenros.replay.inputs import InputDecoder, UndecodableChannel
from zenros.replay.outbag import OutputBag

T0 = 1_000_000_000


def write(path: Path, gains: list[float]) -> Path:
    bag = OutputBag(path)
    for i, g in enumerate(gains):
        bag.add("/cmd_vel", Twist(linear=Vector3(x=g), angular=Vector3(z=0.5 * i)),
                T0 + i * 50_000_000)
        scan = LaserScan(ranges=np.full(8, 1.5 + i, np.float32), range_max=10.0)
        scan.header.stamp = Time(sec=1 + i)
        bag.add("/scan", scan, T0 + i * 50_000_000 + 1, "be+5")
    bag.close()
    return path


def test_the_same_messages_make_the_same_bytes_and_read_back(tmp_path: Path) -> None:
    a = write(tmp_path / "a.mcap", [0.1, 0.2, 0.3])
    b = write(tmp_path / "b.mcap", [0.1, 0.2, 0.3])
    assert a.read_bytes() == b.read_bytes()
    dec = InputDecoder()
    msgs = list(iter_messages(bag_files(a)))
    assert [m.channel.topic for m in msgs] == ["/cmd_vel", "/scan"] * 3
    assert msgs[1].channel.metadata == {"zenoh_encoding": "application/msgpack;sensor_msgs/LaserScan",
                                        "qos": "be+5"}
    assert msgs[1].publish_time == 10**9  # the header's stamp
    assert dec.decode(msgs[2]).linear.x == 0.2
    assert list(dec.decode(msgs[3]).ranges) == [2.5] * 8
    assert compare_bags(a, b) is None


def test_the_first_difference_names_topic_time_field_and_values(tmp_path: Path) -> None:
    a = write(tmp_path / "a.mcap", [0.1, 0.2, 0.3])
    b = write(tmp_path / "b.mcap", [0.1, 0.25, 0.3])
    d = compare_bags(a, b)
    assert d is not None
    assert (d.index, d.topic, d.time_ns, d.path, d.a, d.b) == (
        2, "/cmd_vel", T0 + 50_000_000, ".linear.x", 0.2, 0.25)
    assert "/cmd_vel at 1.050000000 s, .linear.x: 0.2 != 0.25" in str(d)


def test_a_bag_that_ends_early_differs_at_its_end(tmp_path: Path) -> None:
    a = write(tmp_path / "a.mcap", [0.1, 0.2])
    b = write(tmp_path / "b.mcap", [0.1])
    d = compare_bags(a, b)
    assert d is not None and d.index == 2 and d.path == "(message)" and d.b is None


def test_field_differences() -> None:
    assert first_field_difference({"a": [1, 2]}, {"a": [1, 3]}) == (".a[1]", 2, 3)
    assert first_field_difference({"a": [1]}, {"a": [1, 2]}) == (".a.length", 1, 2)
    assert first_field_difference({"x": math.nan}, {"x": math.nan}) is None
    assert first_field_difference({"x": 0.0}, {"x": -0.0}) == (".x", 0.0, -0.0)  # bit for bit
    assert first_field_difference({"x": 1}, {"y": 1}) == (".x", 1, None)


def test_a_channel_of_unknown_type_is_refused_clearly(tmp_path: Path) -> None:
    from zenros.bag.writer import ChunkBuffer, McapFile

    f = McapFile(tmp_path / "u.mcap")
    f.add_channel(1, "/x", "json", 0, {"zenoh_encoding": "application/json;nope_msgs/Nope"})
    chunk = ChunkBuffer()
    chunk.add(1, 1, T0, T0, b"{}")
    f.write_chunk(chunk)
    f.finish()
    m = next(iter_messages([tmp_path / "u.mcap"]))
    with pytest.raises(UndecodableChannel, match="unknown message type 'nope_msgs/Nope'"):
        InputDecoder().decode(m)
