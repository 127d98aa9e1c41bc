"""Messages more than one device publishes (odometry, transforms), built from plain values."""

from __future__ import annotations

from zenros.message import Float64Array, to_array
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
from zenros.msgs.std_msgs import Header
from zenros.se2 import Pose2
from zenros.tf.convert import yaw_to_msg

__all__ = ["covariance", "odometry", "transform"]

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
