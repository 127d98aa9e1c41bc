"""Messages the chassis publishes, built from the simulation's state (no Zenoh here)."""

from __future__ import annotations


import numpy as np
from zenros.message import Float32Array, Float64Array, to_array
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import (
    Point,
    Pose,
    PoseWithCovariance,
    Transform,
    TransformStamped,
    Twist,
    TwistWithCovariance,
    Vector3,
)
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.sensor_msgs import BatteryState, LaserScan
from zenros.msgs.std_msgs import Header
from zenros.se2 import Pose2
from zenros.tf.convert import yaw_to_msg

from .battery import Battery
from .laser import LaserConfig

__all__ = ["battery_state", "covariance", "laser_scan", "odometry", "transform"]

_ZERO_COV: Float64Array = to_array(Float64Array, [0.0] * 36)


def covariance(values: list[float]) -> Float64Array:
    """A 6x6 covariance as the flat float64 array the messages carry."""
    arr: Float64Array = to_array(Float64Array, values)
    return arr


def odometry(stamp: Time, frame: str, child: str, pose: Pose2, linear: float, angular: float,
             pose_cov: Float64Array | None = None, twist_cov: Float64Array | None = None
             ) -> Odometry:
    """``nav_msgs/Odometry``: the pose of ``child`` in ``frame``; the twist in ``child``."""
    return Odometry(
        header=Header(stamp=stamp, frame_id=frame),
        child_frame_id=child,
        pose=PoseWithCovariance(
            pose=Pose(position=Point(x=pose.x, y=pose.y), orientation=yaw_to_msg(pose.theta)),
            covariance=_ZERO_COV if pose_cov is None else pose_cov),
        twist=TwistWithCovariance(
            twist=Twist(linear=Vector3(x=linear), angular=Vector3(z=angular)),
            covariance=_ZERO_COV if twist_cov is None else twist_cov),
    )


def transform(stamp: Time, parent: str, child: str, pose: Pose2, z: float = 0.0
              ) -> TransformStamped:
    return TransformStamped(
        header=Header(stamp=stamp, frame_id=parent), child_frame_id=child,
        transform=Transform(translation=Vector3(x=pose.x, y=pose.y, z=z),
                            rotation=yaw_to_msg(pose.theta)))


def laser_scan(stamp: Time, frame: str, config: LaserConfig, ranges: np.ndarray,
               scan_time: float) -> LaserScan:
    scan_ranges: Float32Array = to_array(Float32Array, ranges)  # a view: float32 already
    return LaserScan(
        header=Header(stamp=stamp, frame_id=frame),
        angle_min=config.angle_min, angle_max=config.angle_max,
        angle_increment=config.angle_increment, time_increment=0.0, scan_time=scan_time,
        range_min=config.range_min, range_max=config.range_max, ranges=scan_ranges,
    )


def battery_state(stamp: Time, frame: str, battery: Battery, docked: bool) -> BatteryState:
    if battery.charging:
        status = BatteryState.POWER_SUPPLY_STATUS_CHARGING
    elif docked and battery.full:
        status = BatteryState.POWER_SUPPLY_STATUS_FULL
    else:
        status = BatteryState.POWER_SUPPLY_STATUS_DISCHARGING
    c = battery.config
    return BatteryState(
        header=Header(stamp=stamp, frame_id=frame),
        voltage=battery.voltage, temperature=25.0, current=battery.current,
        charge=battery.charge, capacity=c.capacity, design_capacity=c.capacity,
        percentage=battery.percentage, power_supply_status=status,
        power_supply_health=1,  # GOOD
        power_supply_technology=2,  # LION
        present=True,
    )
