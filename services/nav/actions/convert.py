"""Conversions between nav's plain values (Pose2, numpy paths) and ROS messages."""

from __future__ import annotations

import math

import numpy as np
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import (
    Point,
    Pose,
    Pose2D,
    PoseStamped,
    PoseWithCovariance,
    PoseWithCovarianceStamped,
    Transform,
    TransformStamped,
    Vector3,
)
from zenros.msgs.nav_msgs import Path
from zenros.msgs.std_msgs import Header
from zenros.se2 import Pose2
from zenros.tf.convert import yaw_from_msg, yaw_to_msg

__all__ = [
    "PoseReader",
    "PoseStream",
    "path_from_msg",
    "path_to_msg",
    "pose2_from_msg",
    "pose2_from_pose2d",
    "pose2_to_msg",
    "pose2_to_pose2d",
    "pose_stamped",
    "pose_with_covariance",
    "transform_stamped",
]


def pose2_from_msg(pose: Pose) -> Pose2:
    """The planar part of a pose; raises ValueError for NaN/inf or a zero quaternion."""
    q = pose.orientation
    x, y = pose.position.x, pose.position.y
    # one test for the common case (called for every odometry message): a sum of finite
    # values is finite unless it overflows, and then the values are looked at one by one
    if not math.isfinite(x + y + q.x + q.y + q.z + q.w):
        values = (x, y, q.x, q.y, q.z, q.w)
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"pose has a non-finite value: {values}")
    if q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w < 1e-12:
        raise ValueError("pose orientation is a zero quaternion")
    return Pose2(x, y, yaw_from_msg(q))


class PoseReader:
    """`pose2_from_msg` that remembers the pose it read last: a message sharing that pose
    part (an in-process publisher at rest sends the same one at every stamp; messages are
    read-only) is not read again. Thread safe (one attribute holds the part and its pose)."""

    __slots__ = ("_last",)

    def __init__(self) -> None:
        self._last: tuple[Pose | None, Pose2] = (None, Pose2())

    def __call__(self, pose: Pose) -> Pose2:
        last = self._last
        if last[0] is pose:
            return last[1]
        out = pose2_from_msg(pose)  # raises before anything is remembered
        self._last = (pose, out)
        return out


def pose2_to_msg(p: Pose2) -> Pose:
    return Pose(position=Point(x=p.x, y=p.y), orientation=yaw_to_msg(p.theta))


def pose2_from_pose2d(p: Pose2D) -> Pose2:
    out = Pose2(p.x, p.y, p.theta)
    if not out.is_finite():
        raise ValueError(f"pose has a non-finite value: {tuple(out)}")
    return out


def pose2_to_pose2d(p: Pose2) -> Pose2D:
    return Pose2D(x=p.x, y=p.y, theta=p.theta)


def pose_stamped(p: Pose2, stamp: Time, frame_id: str = "map") -> PoseStamped:
    return PoseStamped(header=Header(stamp=stamp, frame_id=frame_id), pose=pose2_to_msg(p))


def pose_with_covariance(p: Pose2, stamp: Time, cov_xy: float, cov_yaw: float,
                         frame_id: str = "map") -> PoseWithCovarianceStamped:
    msg = PoseWithCovarianceStamped(header=Header(stamp=stamp, frame_id=frame_id))
    msg.pose.pose = pose2_to_msg(p)
    cov = np.zeros(36)
    cov[0] = cov[7] = cov_xy
    cov[35] = cov_yaw
    msg.pose.covariance = cov.view(type(msg.pose.covariance))
    return msg


def transform_stamped(p: Pose2, stamp: Time, parent: str, child: str) -> TransformStamped:
    return TransformStamped(
        header=Header(stamp=stamp, frame_id=parent), child_frame_id=child,
        transform=Transform(translation=Vector3(x=p.x, y=p.y),
                            rotation=yaw_to_msg(p.theta)))


class PoseStream:
    """``robot_pose`` messages and TF links of poses that mostly stay (a robot at rest),
    stamped anew each time: while the pose is the last one's, the message shares the last
    one's pose part (messages are read-only once published) instead of building it again."""

    def __init__(self, cov_xy: float, cov_yaw: float, frame_id: str = "map") -> None:
        self.frame_id = frame_id
        self._template = pose_with_covariance(Pose2(), Time(), cov_xy, cov_yaw, frame_id)
        self._pose: tuple[Pose2, PoseWithCovariance] | None = None
        self._links: dict[tuple[str, str], tuple[Pose2, Transform]] = {}

    def pose_with_covariance(self, p: Pose2, stamp: Time) -> PoseWithCovarianceStamped:
        """As `pose_with_covariance` with this stream's covariance and frame."""
        last = self._pose
        if last is None or last[0] != p:
            last = self._pose = (p, PoseWithCovariance(
                pose=pose2_to_msg(p), covariance=self._template.pose.covariance))
        return PoseWithCovarianceStamped(header=Header(stamp=stamp, frame_id=self.frame_id),
                                         pose=last[1])

    def transform_stamped(self, p: Pose2, stamp: Time, parent: str, child: str
                          ) -> TransformStamped:
        """As `transform_stamped`."""
        last = self._links.get((parent, child))
        if last is None or last[0] != p:
            last = self._links[(parent, child)] = (p, Transform(
                translation=Vector3(x=p.x, y=p.y), rotation=yaw_to_msg(p.theta)))
        return TransformStamped(header=Header(stamp=stamp, frame_id=parent),
                                child_frame_id=child, transform=last[1])


def path_to_msg(xy: np.ndarray, stamp: Time, frame_id: str = "map",
                final_yaw: float | None = None) -> Path:
    """A ``nav_msgs/Path`` through the (N, 2) points; each pose faces the next point."""
    poses: list[PoseStamped] = []
    n = len(xy)
    header = Header(stamp=stamp, frame_id=frame_id)
    for i in range(n):
        if i + 1 < n:
            yaw = math.atan2(xy[i + 1, 1] - xy[i, 1], xy[i + 1, 0] - xy[i, 0])
        elif final_yaw is not None:
            yaw = final_yaw
        elif n > 1:
            yaw = math.atan2(xy[i, 1] - xy[i - 1, 1], xy[i, 0] - xy[i - 1, 0])
        else:
            yaw = 0.0
        poses.append(PoseStamped(header=header, pose=pose2_to_msg(
            Pose2(float(xy[i, 0]), float(xy[i, 1]), yaw))))
    return Path(header=header, poses=poses)


def path_from_msg(path: Path) -> tuple[np.ndarray, float | None]:
    """The (N, 2) points of a path and the yaw of its last pose (None if empty).

    Raises:
        ValueError: a pose is not finite.
    """
    pts = [pose2_from_msg(ps.pose) for ps in path.poses]
    if not pts:
        return np.zeros((0, 2)), None
    return np.array([(p.x, p.y) for p in pts], dtype=float), pts[-1].theta
