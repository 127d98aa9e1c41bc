"""CDR codec benchmark: zenros.ros2's encode + decode against rclpy's own serializer.

The reference is ``rclpy.serialization.serialize_message`` / ``deserialize_message`` (the ROS 2
wheels, extra ``ros2``), timed interleaved with zenros's CDR codec on the same values in the same
run, so load on the machine hits both. zenros's own JSON/MessagePack codec is timed beside them.
Without the wheels, the rclpy columns are left out. Prints one JSON line.
"""

from __future__ import annotations

import random
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from _harness import emit
from zenros.codec import codec_for
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.sensor_msgs import LaserScan
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


def main() -> None:
    rnd = random.Random(7)
    odom = Odometry()
    odom.pose.pose.position.x = rnd.random()
    msgs = {
        "twist": Twist(linear=Vector3(x=1.0)),
        "scan720": LaserScan(ranges=np.ones(720, dtype=np.float32)),
        "odometry": odom,
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
    emit("ros2_cdr", metrics)


if __name__ == "__main__":
    main()
