"""A small bag as ROS records it, written with rosbags' own writers (docs/bags.md, "Bags
recorded with ROS"; the tests of `zenros.bag.foreign`):

    python scripts/make_ros_bag.py OUT [--storage sqlite3|mcap|ros1] [-n N] [--unknown]
    python scripts/make_ros_bag.py OUT --from ZENROS_BAG [--storage sqlite3|mcap]

OUT is a rosbag2 directory (sqlite3, mcap storage) or a ROS 1 ``.bag`` file (ros1). N steps
(default 10) 100 ms apart from 1,700,000,000 s: /cmd_vel (geometry_msgs/Twist), /odom
(nav_msgs/Odometry), /scan (sensor_msgs/LaserScan), /tf (tf2_msgs/TFMessage) each step,
/map (nav_msgs/OccupancyGrid, transient-local/latched) and /goal_pose
(geometry_msgs/PoseStamped) once at the start. ``--unknown`` adds /custom of a type zenros
does not have (my_robot_msgs/Battery, defined in the bag). Values follow the step number i
(see `values` below), so a reader can check them. ``--from`` re-writes a zenros bag as a
rosbag2 bag instead (the messages CDR-encoded, as ``ros2 bag record`` would have stored
them: docs/replay.md replays one into nav). Needs rosbags (``pip install
'zenros[rosbags]'``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np
from rosbags.rosbag1 import Writer as Writer1
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Writer2
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

T0 = 1_700_000_000 * 10**9
STEP = 100_000_000  # ns
BEAMS = 36
MAP_W, MAP_H = 4, 3
BATTERY = "my_robot_msgs/msg/Battery"
BATTERY_MSG = "float32 voltage\nuint8 percent\n"


def _store(ros1: bool, unknown: bool) -> Typestore:
    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_KILTED)
    if ros1:  # rosbags' Noetic store leaves tf2_msgs out: its definition, as ROS 1 has it
        store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms\n",
                                          "tf2_msgs/msg/TFMessage"))
    if unknown:
        store.register(get_types_from_msg(BATTERY_MSG, BATTERY))
    return store


def _header(store: Typestore, ros1: bool, t: int, frame: str, seq: int) -> Any:
    stamp = store.types["builtin_interfaces/msg/Time"](sec=t // 10**9, nanosec=t % 10**9)
    if ros1:
        return store.types["std_msgs/msg/Header"](seq=seq, stamp=stamp, frame_id=frame)
    return store.types["std_msgs/msg/Header"](stamp=stamp, frame_id=frame)


def values(store: Typestore, ros1: bool, i: int) -> dict[str, tuple[str, Any]]:
    """The messages of step i by topic: (ROS type, rosbags message)."""
    ty = store.types
    t = T0 + i * STEP
    vec = ty["geometry_msgs/msg/Vector3"]
    point = ty["geometry_msgs/msg/Point"]
    quat = ty["geometry_msgs/msg/Quaternion"]
    twist = ty["geometry_msgs/msg/Twist"](linear=vec(x=0.1 * i, y=0.0, z=0.0),
                                          angular=vec(x=0.0, y=0.0, z=-0.05 * i))
    pose = ty["geometry_msgs/msg/Pose"](position=point(x=0.5 * i, y=-0.25 * i, z=0.0),
                                        orientation=quat(x=0.0, y=0.0, z=0.0, w=1.0))
    cov = np.arange(36, dtype=np.float64) * 0.01
    odom = ty["nav_msgs/msg/Odometry"](
        header=_header(store, ros1, t, "odom", i), child_frame_id="base_link",
        pose=ty["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=cov),
        twist=ty["geometry_msgs/msg/TwistWithCovariance"](twist=twist, covariance=cov))
    ranges = (1.0 + 0.01 * np.arange(BEAMS) + 0.1 * i).astype(np.float32)
    scan = ty["sensor_msgs/msg/LaserScan"](
        header=_header(store, ros1, t, "laser", i), angle_min=-np.pi, angle_max=np.pi,
        angle_increment=2 * np.pi / BEAMS, time_increment=0.0, scan_time=0.1, range_min=0.1,
        range_max=30.0, ranges=ranges, intensities=np.zeros(BEAMS, dtype=np.float32))
    tf = ty["tf2_msgs/msg/TFMessage"](transforms=[ty["geometry_msgs/msg/TransformStamped"](
        header=_header(store, ros1, t, "odom", i), child_frame_id="base_link",
        transform=ty["geometry_msgs/msg/Transform"](
            translation=vec(x=0.5 * i, y=-0.25 * i, z=0.0), rotation=quat(x=0.0, y=0.0, z=0.0,
                                                                          w=1.0)))])
    out: dict[str, tuple[str, Any]] = {
        "/cmd_vel": ("geometry_msgs/msg/Twist", twist),
        "/odom": ("nav_msgs/msg/Odometry", odom),
        "/scan": ("sensor_msgs/msg/LaserScan", scan),
        "/tf": ("tf2_msgs/msg/TFMessage", tf),
    }
    if i == 0:
        info = ty["nav_msgs/msg/MapMetaData"](
            map_load_time=ty["builtin_interfaces/msg/Time"](sec=T0 // 10**9, nanosec=0),
            resolution=0.05, width=MAP_W, height=MAP_H, origin=pose)
        cells = np.array([0, 100, -1, 0] * MAP_H, dtype=np.int8)
        out["/map"] = ("nav_msgs/msg/OccupancyGrid", ty["nav_msgs/msg/OccupancyGrid"](
            header=_header(store, ros1, t, "map", 0), info=info, data=cells))
        out["/goal_pose"] = ("geometry_msgs/msg/PoseStamped", ty["geometry_msgs/msg/PoseStamped"](
            header=_header(store, ros1, t, "map", 0), pose=pose))
    return out


def _serialize(store: Typestore, ros1: bool, msg: Any, ros_type: str) -> bytes:
    data = store.serialize_ros1(msg, ros_type) if ros1 else store.serialize_cdr(msg, ros_type)
    return bytes(data)


def write_bag(out: Path, storage: str = "sqlite3", n: int = 10, unknown: bool = False) -> Path:
    """Write the bag; returns ``out``."""
    ros1 = storage == "ros1"
    store = _store(ros1, unknown)
    steps = [values(store, ros1, i) for i in range(n)]
    if unknown:
        for i, step in enumerate(steps):
            step["/custom"] = (BATTERY, store.types[BATTERY](voltage=24.0 - 0.1 * i,
                                                              percent=90 - i))
    if ros1:
        with Writer1(out) as w1:
            conns1: dict[str, Any] = {}
            for i, step in enumerate(steps):
                for topic, (ros_type, msg) in step.items():
                    if topic not in conns1:
                        conns1[topic] = w1.add_connection(
                            topic, ros_type, typestore=store,
                            latching=1 if topic == "/map" else None)
                    w1.write(conns1[topic], T0 + i * STEP, _serialize(store, True, msg, ros_type))
        return out
    plugin = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}[storage]
    latched = _latched_qos()
    with Writer2(out, version=9, storage_plugin=plugin) as w2:
        conns2: dict[str, Any] = {}
        for i, step in enumerate(steps):
            for topic, (ros_type, msg) in step.items():
                if topic not in conns2:
                    conns2[topic] = w2.add_connection(
                        topic, ros_type, typestore=store,
                        offered_qos_profiles=[latched] if topic == "/map" else [])
                w2.write(conns2[topic], T0 + i * STEP, _serialize(store, False, msg, ros_type))
    return out


def _latched_qos() -> Any:
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )

    never = QosTime(sec=0, nsec=0)
    return Qos(QosHistory.KEEP_LAST, 1, QosReliability.RELIABLE, QosDurability.TRANSIENT_LOCAL,
               never, never, QosLiveliness.AUTOMATIC, never, False)


def from_zenros_bag(src: Path, out: Path, storage: str = "sqlite3") -> Path:
    """A zenros bag re-written as ``ros2 bag record`` would have stored the same messages: a
    rosbag2 directory (``storage`` sqlite3 or mcap), each message CDR-encoded by zenros's
    codec under its ROS 2 name, at the same log times and in the same order, with each
    channel's QoS. Only the standard types (rosbags' Kilted store has their definitions);
    a channel of another type is left out."""
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )
    from zenros.bag import bag_files, iter_messages
    from zenros.codec import decode_any
    from zenros.qos import QoSProfile, Reliability
    from zenros.ros2 import cdr_codec, ros_name_of

    store = get_typestore(Stores.ROS2_KILTED)
    never = QosTime(sec=0, nsec=0)
    plugin = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}[storage]
    with Writer2(out, version=9, storage_plugin=plugin) as w:
        conns: dict[tuple[str, str], Any] = {}
        for m in iter_messages(bag_files(src)):
            msg = decode_any(m.data, m.channel.metadata["zenoh_encoding"])
            name = ros_name_of(type(msg))
            if name not in store.types:
                continue
            key = (m.channel.topic, name)
            if key not in conns:
                q = QoSProfile.from_tag(m.channel.metadata.get("qos", "rel+10"))
                reliable = q.reliability == Reliability.RELIABLE
                qos = Qos(QosHistory.KEEP_LAST, q.depth,
                          QosReliability.RELIABLE if reliable else QosReliability.BEST_EFFORT,
                          QosDurability.TRANSIENT_LOCAL if q.latched else QosDurability.VOLATILE,
                          never, never, QosLiveliness.AUTOMATIC, never, False)
                conns[key] = w.add_connection(m.channel.topic, name, typestore=store,
                                              offered_qos_profiles=[qos])
            w.write(conns[key], m.log_time, cdr_codec(type(msg)).encode(msg))
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0] if __doc__ else None)
    p.add_argument("out", type=Path)
    p.add_argument("--storage", choices=("sqlite3", "mcap", "ros1"), default="sqlite3")
    p.add_argument("-n", type=int, default=10, help="steps, 100 ms apart")
    p.add_argument("--unknown", action="store_true", help="add a topic of a type zenros lacks")
    p.add_argument("--from", dest="source", type=Path, metavar="ZENROS_BAG",
                   help="re-write this zenros bag's messages instead (rosbag2 storage only)")
    args = p.parse_args(argv)
    if args.out.exists():
        print(f"{args.out} exists: give a new path", file=sys.stderr)
        return 2
    if args.source is not None:
        if args.storage == "ros1":
            print("--from writes rosbag2 bags (--storage sqlite3 or mcap)", file=sys.stderr)
            return 2
        from_zenros_bag(args.source, args.out, args.storage)
    else:
        write_bag(args.out, args.storage, args.n, args.unknown)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
