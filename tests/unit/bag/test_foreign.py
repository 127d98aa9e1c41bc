"""Bags recorded with ROS (rosbag2 SQLite3 and MCAP, ROS 1 .bag), written by rosbags' own
writers, read through zenros.bag's reader API: bag info, iteration, the converted values, and
clear errors for bad bags."""

from __future__ import annotations

import logging
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from ros_bags import STORAGES, make
from zenros.bag import BagError, bag_files, bag_info, foreign, format_info, iter_messages
from zenros.codec import decode_any
from zenros.msgs.geometry_msgs import PoseStamped, Twist
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.tf2_msgs import TFMessage

pytest.importorskip("rosbags", reason="rosbags not installed (pip install -e '.[rosbags]')")

T0 = 1_700_000_000 * 10**9
STEP = 100_000_000
N = 10


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("ros_bags")
    return {s: make(d, s, N, unknown=True) for s in STORAGES}


def decoded(bag: Path, **kw: Any) -> list[tuple[int, str, Any]]:
    return [(m.log_time, m.channel.topic, decode_any(m.data, m.channel.metadata["zenoh_encoding"]))
            for m in iter_messages(bag_files(bag), **kw)]


@pytest.mark.parametrize("storage", STORAGES)
def test_info_names_types_counts_and_the_skipped_topic(bags: dict[str, Path], storage: str) -> None:
    info = bag_info(bags[storage])
    assert info.recorded_with_ros and info.storage == {"ros1": "rosbag1"}.get(storage, storage)
    assert info.messages == 4 * N + 2 + N  # four topics a step, /map and /goal_pose, /custom
    assert (info.start, info.end) == (T0, T0 + (N - 1) * STEP)
    by_topic = {t.topic: t for t in info.topics}
    expected = {
        "/cmd_vel": ("geometry_msgs/msg/Twist", N), "/odom": ("nav_msgs/msg/Odometry", N),
        "/scan": ("sensor_msgs/msg/LaserScan", N), "/tf": ("tf2_msgs/msg/TFMessage", N),
        "/map": ("nav_msgs/msg/OccupancyGrid", 1), "/goal_pose": ("geometry_msgs/msg/PoseStamped", 1),
        "/custom": ("my_robot_msgs/msg/Battery", N)}
    if storage == "ros1":  # named as ROS 1 names them
        expected = {k: (t.replace("/msg/", "/"), n) for k, (t, n) in expected.items()}
    assert {t: (v.type, v.count) for t, v in by_topic.items()} == expected
    assert by_topic["/custom"].skipped == "zenros has no type my_robot_msgs/msg/Battery"
    assert not any(t.skipped for t in info.topics if t.topic != "/custom")
    text = format_info(info)
    assert "(recorded with ROS)" in text
    assert "NOT PLAYED: zenros has no type my_robot_msgs/msg/Battery" in text
    assert f"Serialization Format: {'ros1' if storage == 'ros1' else 'cdr'}" in text


def check_values(got: list[tuple[int, str, Any]]) -> None:
    """What scripts/make_ros_bag.py wrote, step by step, as zenros's messages."""
    times = [t for t, _, _ in got]
    assert times == sorted(times)
    by_topic: dict[str, list[tuple[int, Any]]] = {}
    for t, topic, msg in got:
        by_topic.setdefault(topic, []).append((t, msg))
    assert {k: len(v) for k, v in by_topic.items()} == {
        "/cmd_vel": N, "/odom": N, "/scan": N, "/tf": N, "/map": 1, "/goal_pose": 1}
    for i, (t, tw) in enumerate(by_topic["/cmd_vel"]):
        assert t == T0 + i * STEP and isinstance(tw, Twist)
        assert tw.linear.x == pytest.approx(0.1 * i) and tw.angular.z == pytest.approx(-0.05 * i)
    cov = np.arange(36) * 0.01
    for i, (t, od) in enumerate(by_topic["/odom"]):
        assert isinstance(od, Odometry)
        assert (od.header.stamp.sec, od.header.stamp.nanosec) == divmod(t, 10**9)
        assert od.header.frame_id == "odom" and od.child_frame_id == "base_link"
        assert od.pose.pose.position.x == pytest.approx(0.5 * i)
        assert od.pose.pose.position.y == pytest.approx(-0.25 * i)
        assert od.pose.pose.orientation.w == 1.0
        np.testing.assert_allclose(od.pose.covariance, cov)
        assert od.twist.twist.linear.x == pytest.approx(0.1 * i)
    for i, (_, sc) in enumerate(by_topic["/scan"]):
        assert isinstance(sc, LaserScan) and sc.header.frame_id == "laser"
        assert sc.ranges.dtype == np.float32 and len(sc.ranges) == 36
        np.testing.assert_array_equal(
            sc.ranges, (1.0 + 0.01 * np.arange(36) + 0.1 * i).astype(np.float32))
        assert sc.angle_min == pytest.approx(-math.pi) and sc.range_max == 30.0
    for i, (_, tf) in enumerate(by_topic["/tf"]):
        assert isinstance(tf, TFMessage) and len(tf.transforms) == 1
        tr = tf.transforms[0]
        assert (tr.header.frame_id, tr.child_frame_id) == ("odom", "base_link")
        assert tr.transform.translation.x == pytest.approx(0.5 * i)
    (_, grid), = by_topic["/map"]
    assert isinstance(grid, OccupancyGrid)
    assert (grid.info.width, grid.info.height, grid.info.resolution) == (4, 3, pytest.approx(0.05))
    assert grid.info.map_load_time.sec == T0 // 10**9
    assert grid.data.dtype == np.int8 and grid.data.tolist() == [0, 100, -1, 0] * 3
    (_, goal), = by_topic["/goal_pose"]
    assert isinstance(goal, PoseStamped) and goal.header.frame_id == "map"


@pytest.mark.parametrize("storage", STORAGES)
def test_messages_convert_to_zenros_types_in_log_time_order(bags: dict[str, Path],
                                                            storage: str) -> None:
    got = decoded(bags[storage])
    check_values(got)
    m = next(iter_messages(bag_files(bags[storage]), topics=["/map"]))
    # the shape the player publishes: a bulk type as MessagePack, with the recorded QoS
    assert m.channel.message_encoding == "msgpack" and m.schema is not None
    assert m.schema.name == "nav_msgs/OccupancyGrid" and m.schema.encoding == "jsonschema"
    assert m.channel.metadata["zenoh_encoding"] == "application/msgpack;nav_msgs/OccupancyGrid"
    assert m.channel.metadata["qos"] == "rel+tl+1"  # transient local / latched


def test_topics_and_start_filter(bags: dict[str, Path]) -> None:
    got = decoded(bags["sqlite3"], topics=["/scan", "/cmd_vel"], start=T0 + 5 * STEP)
    assert [(t, topic) for t, topic, _ in got] == [
        (T0 + i * STEP, topic) for i in range(5, N) for topic in ("/cmd_vel", "/scan")]


def test_the_field_by_field_path_gives_what_the_cdr_codec_gives(
        bags: dict[str, Path], monkeypatch: pytest.MonkeyPatch) -> None:
    """A ROS 2 definition that differs from zenros's (another distro) goes through rosbags'
    deserialiser and the builder: the same messages as zenros's own CDR codec."""
    fast = decoded(bags["mcap"])
    monkeypatch.setattr(foreign, "type_hash", lambda name: "RIHS01_other")
    slow = decoded(bags["mcap"])
    assert slow == fast
    check_values(slow)


def test_ros1_names_that_differ_in_case_and_the_dropped_seq() -> None:
    from rosbags.typesys import Stores, get_typestore
    from zenros.bag.ros_convert import builder_for
    from zenros.msgs.sensor_msgs import CameraInfo

    store = get_typestore(Stores.ROS1_NOETIC)
    ty = store.types
    header = ty["std_msgs/msg/Header"](
        seq=7, stamp=ty["builtin_interfaces/msg/Time"](sec=3, nanosec=4), frame_id="cam")
    roi = ty["sensor_msgs/msg/RegionOfInterest"](x_offset=1, y_offset=2, height=3, width=4,
                                                  do_rectify=True)
    ros = ty["sensor_msgs/msg/CameraInfo"](
        header=header, height=480, width=640, distortion_model="plumb_bob",
        D=np.array([0.1, 0.2, 0.0, 0.0, 0.0]), K=np.arange(9, dtype=np.float64),
        R=np.eye(3).ravel(), P=np.arange(12, dtype=np.float64), binning_x=0, binning_y=0, roi=roi)
    raw = store.serialize_ros1(ros, "sensor_msgs/msg/CameraInfo")
    info = builder_for(CameraInfo)(store.deserialize_ros1(raw, "sensor_msgs/msg/CameraInfo"))
    assert isinstance(info, CameraInfo)
    assert (info.header.stamp.sec, info.header.stamp.nanosec, info.header.frame_id) == (3, 4, "cam")
    assert list(info.k) == list(range(9)) and list(info.d) == [0.1, 0.2, 0.0, 0.0, 0.0]
    assert list(info.p) == list(range(12)) and info.roi.do_rectify is True
    assert foreign.ros1_alias("tf/msg/tfMessage") == "tf2_msgs/msg/TFMessage"


@pytest.mark.parametrize("mode", ["FILE", "MESSAGE"])
def test_a_zstd_compressed_rosbag2(tmp_path: Path, mode: str) -> None:
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_KILTED)
    string = store.types["std_msgs/msg/String"]
    w = Writer(tmp_path / "z", version=9, storage_plugin=StoragePlugin.SQLITE3)
    w.set_compression(CompressionMode[mode], CompressionFormat.ZSTD)
    with w:
        conn = w.add_connection("/chatter", "std_msgs/msg/String", typestore=store)
        for i in range(5):
            w.write(conn, T0 + i, store.serialize_cdr(string(data=f"hi {i}"),
                                                      "std_msgs/msg/String"))
    info = bag_info(tmp_path / "z")
    assert info.compression == [f"zstd ({mode.lower()})"] and info.messages == 5
    assert [msg.data for _, _, msg in decoded(tmp_path / "z")] == [f"hi {i}" for i in range(5)]


# ------------------------------------------------------------------ bad input


def test_a_corrupt_db3_is_a_clear_error(tmp_path: Path) -> None:
    bad = tmp_path / "broken.db3"
    bad.write_bytes(b"SQLite format 3\x00" + bytes(range(256)) * 8)
    with pytest.raises(BagError, match=r"broken.db3: not a readable ROS bag"):
        bag_info(bad)
    with pytest.raises(BagError, match="not a readable ROS bag"):
        list(iter_messages(bag_files(bad)))
    junk = tmp_path / "junk.db3"
    junk.write_bytes(b"not sqlite at all")
    with pytest.raises(BagError, match="junk.db3: not a readable ROS bag"):
        bag_info(junk)


def test_a_bad_ros1_bag_and_an_empty_rosbag2_directory(tmp_path: Path) -> None:
    bad = tmp_path / "broken.bag"
    bad.write_bytes(b"#ROSBAG V2.0\n" + b"\xff" * 64)
    with pytest.raises(BagError, match="broken.bag: not a readable ROS bag"):
        bag_info(bad)
    (tmp_path / "meta").mkdir()
    (tmp_path / "meta" / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
    with pytest.raises(BagError, match="metadata.yaml but no .db3 or .mcap"):
        bag_files(tmp_path / "meta")


def test_a_cut_rosbag2_file_is_a_clear_error(bags: dict[str, Path], tmp_path: Path) -> None:
    src = bag_files(bags["mcap"])[0]
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(src.read_bytes()[: src.stat().st_size // 2])
    with pytest.raises(BagError, match="cut.mcap"):
        list(iter_messages(bag_files(cut)))


def _twists(out: Path, bad_at: int | None = None, encoding: str = "cdr") -> Path:
    """A rosbag2 SQLite3 bag of four Twists on /cmd_vel (x = 0..3), the one at ``bad_at``
    cut short, and /other in ``encoding``."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_KILTED)
    twist = store.types["geometry_msgs/msg/Twist"]
    vec = store.types["geometry_msgs/msg/Vector3"]
    with Writer(out, version=9, storage_plugin=StoragePlugin.SQLITE3) as w:
        good = w.add_connection("/cmd_vel", "geometry_msgs/msg/Twist", typestore=store)
        other = w.add_connection("/other", "geometry_msgs/msg/Twist", typestore=store,
                                 serialization_format=encoding)
        for i in range(4):
            data = store.serialize_cdr(twist(linear=vec(x=float(i), y=0.0, z=0.0),
                                             angular=vec(x=0.0, y=0.0, z=0.0)),
                                       "geometry_msgs/msg/Twist")
            w.write(good, T0 + i, bytes(data[:10]) if i == bad_at else data)
            w.write(other, T0 + i, data)
    return out


def test_an_unknown_encoding_is_a_clear_error(tmp_path: Path) -> None:
    bag = _twists(tmp_path / "proto", encoding="protobuf")
    with pytest.raises(BagError, match=r"proto: not a readable ROS bag .*'protobuf'"):
        bag_info(bag)
    with pytest.raises(BagError, match="'protobuf'"):
        list(iter_messages(bag_files(bag)))


def test_a_message_that_does_not_decode_is_skipped_with_one_warning(
        tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    bag = _twists(tmp_path / "cut", bad_at=2)
    with caplog.at_level(logging.WARNING, logger="zenros.bag"):
        got = decoded(bag, topics=["/cmd_vel"])
        decoded(bag, topics=["/cmd_vel"])  # read again: no second warning
    assert [msg.linear.x for _, _, msg in got] == [0.0, 1.0, 3.0]
    warnings = [r.getMessage() for r in caplog.records]
    assert len(warnings) == 1 and "/cmd_vel" in warnings[0] and "does not decode" in warnings[0]


def test_without_rosbags_the_error_names_the_extra(bags: dict[str, Path],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)  # import fails
    with pytest.raises(BagError, match=r"pip install 'zenros\[rosbags\]'"):
        bag_info(bags["sqlite3"])


def test_recover_says_a_ros_bag_is_not_its_to_rebuild(bags: dict[str, Path]) -> None:
    from zenros.bag import recover_bag

    for storage in STORAGES:
        with pytest.raises(BagError, match="was recorded with ROS: recover rebuilds zenros's"):
            recover_bag(bags[storage])


def test_a_ros1_tf_tfmessage_plays_as_tf2_msgs(tmp_path: Path) -> None:
    """ROS 1's legacy tf/tfMessage (tf before tf2) is read as tf2_msgs/TFMessage."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms\n",
                                      "tf/msg/tfMessage"))
    ty = store.types
    vec = ty["geometry_msgs/msg/Vector3"](x=1.5, y=0.0, z=0.0)
    stamped = ty["geometry_msgs/msg/TransformStamped"](
        header=ty["std_msgs/msg/Header"](seq=3, stamp=ty["builtin_interfaces/msg/Time"](
            sec=5, nanosec=6), frame_id="odom"), child_frame_id="base_link",
        transform=ty["geometry_msgs/msg/Transform"](
            translation=vec, rotation=ty["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0,
                                                                          w=1.0)))
    out = tmp_path / "old_tf.bag"
    with Writer(out) as w:
        conn = w.add_connection("/tf", "tf/msg/tfMessage", typestore=store)
        w.write(conn, T0, store.serialize_ros1(ty["tf/msg/tfMessage"](transforms=[stamped]),
                                               "tf/msg/tfMessage"))
    (t, topic, msg), = decoded(out)
    assert isinstance(msg, TFMessage) and topic == "/tf" and t == T0
    tr = msg.transforms[0]
    assert (tr.header.stamp.sec, tr.header.stamp.nanosec, tr.header.frame_id) == (5, 6, "odom")
    assert tr.transform.translation.x == 1.5 and tr.transform.rotation.w == 1.0


@pytest.mark.parametrize("plugin", ["SQLITE3", "MCAP"])
def test_a_humble_definition_that_differs_from_zenros(tmp_path: Path, plugin: str) -> None:
    """Humble's sensor_msgs/Range has no ``variance`` (Kilted's and zenros's has): its type
    hash differs, so rosbags reads it with the bag's own definition and zenros fills the
    field it lacks with its default."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    from zenros.msgs.sensor_msgs import Range
    from zenros.ros2 import type_hash

    store = get_typestore(Stores.ROS2_HUMBLE)
    assert store.hash_rihs01("sensor_msgs/msg/Range") != type_hash("sensor_msgs/msg/Range")
    ty = store.types
    out = tmp_path / "humble"
    with Writer(out, version=9, storage_plugin=StoragePlugin[plugin]) as w:
        conn = w.add_connection("/range", "sensor_msgs/msg/Range", typestore=store)
        for i in range(3):
            r = ty["sensor_msgs/msg/Range"](
                header=ty["std_msgs/msg/Header"](stamp=ty["builtin_interfaces/msg/Time"](
                    sec=1, nanosec=i), frame_id="sonar"), radiation_type=0, field_of_view=0.5,
                min_range=0.1, max_range=4.0, range=1.0 + i)
            w.write(conn, T0 + i, store.serialize_cdr(r, "sensor_msgs/msg/Range"))
    got = [msg for _, _, msg in decoded(out)]
    assert all(isinstance(m, Range) for m in got)
    assert [(m.range, m.header.stamp.nanosec, m.variance) for m in got] == [
        (1.0, 0, 0.0), (2.0, 1, 0.0), (3.0, 2, 0.0)]
    assert got[0].field_of_view == pytest.approx(0.5) and got[0].header.frame_id == "sonar"
