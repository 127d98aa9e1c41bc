"""CDR codec benchmark: zenros.ros2's encode + decode against rclpy's own serializer and
rosbags' pure-Python codec.

The references are ``rclpy.serialization.serialize_message`` / ``deserialize_message`` (the
ROS 2 wheels, extra ``ros2``) and rosbags' ``serialize_cdr`` / ``deserialize_cdr`` (its
``ros2_kilted`` type store; extra ``test``), timed with zenros's CDR codec on the same values
in the same run, so load on the machine hits all. zenros's own JSON/MessagePack codec is
timed beside them. The messages: a Twist, a 720-beam LaserScan, an Odometry, a 640x480 rgb8
Image and a 100,000-point xyz PointCloud2. Without a reference, its columns are left out.
Prints one JSON line.
"""

from __future__ import annotations

import random
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from _harness import emit
from zenros.codec import codec_for
from zenros.images import numpy_to_image
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.std_msgs import Header
from zenros.point_cloud2 import create_cloud_xyz32
from zenros.ros2 import cdr_codec

ROUNDS, LOOPS = 7, 300


def _best(fn: Callable[[], Any]) -> float:
    """The best of ROUNDS runs of LOOPS calls, in microseconds per call."""
    best = float("inf")
    for _ in range(ROUNDS):
        t0 = time.perf_counter()
        for _ in range(LOOPS):
            fn()
        best = min(best, time.perf_counter() - t0)
    return best / LOOPS * 1e6


def _rclpy_pair(msg: Any) -> Callable[[], Any] | None:
    """rclpy's serialize + deserialize of the same values, or None without the wheels."""
    try:
        from rclpy.serialization import deserialize_message, serialize_message
        from rosidl_runtime_py.set_message import set_message_fields
        from rosidl_runtime_py.utilities import get_message
    except ImportError:
        return None
    from zenros.codec import to_builtins
    from zenros.ros2 import ros_name_of

    cls = get_message(ros_name_of(type(msg)))
    ros_msg = cls()
    set_message_fields(ros_msg, to_builtins(msg))
    return lambda: deserialize_message(serialize_message(ros_msg), cls)


def _rosbags_pair(msg: Any) -> Callable[[], Any] | None:
    """rosbags' serialize + deserialize of the same values, or None without rosbags."""
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        return None
    from zenros.ros2 import ros_name_of

    store = get_typestore(Stores.ROS2_KILTED)
    name = ros_name_of(type(msg))
    theirs = store.deserialize_cdr(cdr_codec(type(msg)).encode(msg), name)
    return lambda: store.deserialize_cdr(store.serialize_cdr(theirs, name), name)


def main() -> None:
    rnd = random.Random(7)
    odom = Odometry()
    odom.pose.pose.position.x = rnd.random()
    pixels = np.random.default_rng(7).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    msgs = {
        "twist": Twist(linear=Vector3(x=1.0)),
        "scan720": LaserScan(ranges=np.ones(720, dtype=np.float32)),
        "odometry": odom,
        "image640x480": numpy_to_image(pixels, "rgb8"),
        "cloud100k": create_cloud_xyz32(Header(frame_id="lidar"),
                                        np.random.default_rng(7).random((100_000, 3))),
    }
    metrics: dict[str, float] = {}
    for name, msg in msgs.items():
        cdr, native = cdr_codec(type(msg)), codec_for(type(msg))
        metrics[f"{name}_cdr_us"] = _best(lambda: cdr.decode(cdr.encode(msg)))  # noqa: B023
        metrics[f"{name}_native_us"] = _best(lambda: native.decode(native.encode(msg)))  # noqa: B023
        ref = _rclpy_pair(msg)
        if ref is not None:
            metrics[f"{name}_rclpy_us"] = _best(ref)
            metrics[f"{name}_ratio"] = metrics[f"{name}_cdr_us"] / metrics[f"{name}_rclpy_us"]
        bags = _rosbags_pair(msg)
        if bags is not None:
            metrics[f"{name}_rosbags_us"] = _best(bags)
            metrics[f"{name}_rosbags_ratio"] = (metrics[f"{name}_cdr_us"]
                                                / metrics[f"{name}_rosbags_us"])
    emit("ros2_cdr", metrics)


if __name__ == "__main__":
    main()
