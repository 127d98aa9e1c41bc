"""Conversions from the mapper's plain values (Pose2, grids, tracks) to ROS messages."""

from __future__ import annotations

import math

import numpy as np
from zenros.maps import GridMap
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import (
    Point,
    Pose,
    Pose2D,
    PoseStamped,
    PoseWithCovarianceStamped,
    TransformStamped,
)
from zenros.msgs.nav_msgs import OccupancyGrid, Path
from zenros.msgs.std_msgs import Header
from zenros.se2 import Pose2
from zenros.tf.convert import transform_stamped, yaw_to_msg

__all__ = ["grid_msg", "pose2d", "pose_msg", "pose_with_covariance", "track_msg",
           "transform_msg"]


def pose_msg(p: Pose2) -> Pose:
    return Pose(position=Point(x=p.x, y=p.y), orientation=yaw_to_msg(p.theta))


def pose2d(p: Pose2) -> Pose2D:
    return Pose2D(x=p.x, y=p.y, theta=p.theta)


def grid_msg(cells: np.ndarray, resolution: float, origin: tuple[float, float],
             stamp: Time, frame_id: str) -> OccupancyGrid:
    return GridMap(cells, resolution, (origin[0], origin[1], 0.0)).to_msg(frame_id, stamp)


def track_msg(poses: list[Pose2], stamps: list[Time], frame_id: str, stamp: Time) -> Path:
    return Path(header=Header(stamp=stamp, frame_id=frame_id),
                poses=[PoseStamped(header=Header(stamp=t, frame_id=frame_id), pose=pose_msg(p))
                       for p, t in zip(poses, stamps, strict=True)])


def pose_with_covariance(p: Pose2, cov: np.ndarray, stamp: Time,
                         frame_id: str) -> PoseWithCovarianceStamped:
    """``cov``: 3x3 over (x, y, yaw), placed in the 6x6 message covariance."""
    msg = PoseWithCovarianceStamped(header=Header(stamp=stamp, frame_id=frame_id))
    msg.pose.pose = pose_msg(p)
    full = np.zeros((6, 6))
    idx = [0, 1, 5]
    full[np.ix_(idx, idx)] = cov
    msg.pose.covariance = full.ravel().view(type(msg.pose.covariance))
    return msg


def transform_msg(p: Pose2, stamp: Time, parent: str, child: str) -> TransformStamped:
    half = p.theta / 2
    return transform_stamped(parent, child,
                             (p.x, p.y, 0.0, 0.0, 0.0, math.sin(half), math.cos(half)), stamp)
