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

__all__ = ["OdometryStream", "covariance", "odometry", "transform"]

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


class OdometryStream:
    """Odometry of ``child`` in ``frame`` (and its TF link), stamped anew each time: while
    the pose and the speeds stay those of the last message (a robot at rest), the new
    message shares the last one's pose and twist parts instead of building them again
    (messages are read-only once published), and the TF link its transform."""

    def __init__(self, frame: str, child: str, pose_cov: Float64Array | None = None,
                 twist_cov: Float64Array | None = None) -> None:
        self.frame, self.child = frame, child
        self._pose_cov = _ZERO_COV if pose_cov is None else pose_cov
        self._twist_cov = _ZERO_COV if twist_cov is None else twist_cov
        self._pose: tuple[Pose2, PoseWithCovariance] | None = None
        self._twist: tuple[float, float, TwistWithCovariance] | None = None
        self._link: tuple[Pose2, Transform] | None = None

    def odometry(self, stamp: Time, pose: Pose2, linear: float, angular: float) -> Odometry:
        """The ``nav_msgs/Odometry`` of ``pose`` and the speeds (the twist in ``child``)."""
        last = self._pose
        if last is None or last[0] != pose:
            last = self._pose = (pose, PoseWithCovariance(
                pose=Pose(position=Point(x=pose.x, y=pose.y),
                          orientation=yaw_to_msg(pose.theta)),
                covariance=self._pose_cov))
        twist = self._twist
        if twist is None or twist[0] != linear or twist[1] != angular:
            twist = self._twist = (linear, angular, TwistWithCovariance(
                twist=Twist(linear=Vector3(x=linear), angular=Vector3(z=angular)),
                covariance=self._twist_cov))
        return Odometry(header=Header(stamp=stamp, frame_id=self.frame),
                        child_frame_id=self.child, pose=last[1], twist=twist[2])

    def transform(self, stamp: Time, pose: Pose2) -> TransformStamped:
        """The TF link ``frame`` -> ``child`` at ``pose``."""
        link = self._link
        if link is None or link[0] != pose:
            link = self._link = (pose, Transform(translation=Vector3(x=pose.x, y=pose.y),
                                                 rotation=yaw_to_msg(pose.theta)))
        return TransformStamped(header=Header(stamp=stamp, frame_id=self.frame),
                                child_frame_id=self.child, transform=link[1])
