"""Conversions between geometry_msgs messages, transform tuples and numpy matrices."""

from __future__ import annotations

from ..msgs.builtin_interfaces import Time
from ..msgs.geometry_msgs import (
    Point,
    Pose,
    Quaternion,
    Transform,
    TransformStamped,
    Vector3,
)
from ..msgs.std_msgs import Header
from .matrix import Array, transform_from_matrix, transform_matrix
from .quaternion import Quat, Vec3, quaternion_from_yaw, yaw_from_quaternion
from .rigid import Tf

__all__ = [
    "matrix_from_msg",
    "msg_from_matrix",
    "point_from_msg",
    "point_to_msg",
    "pose_from_msg",
    "pose_to_msg",
    "pose_to_transform",
    "quaternion_from_msg",
    "quaternion_to_msg",
    "transform_from_msg",
    "transform_stamped",
    "transform_to_msg",
    "transform_to_pose",
    "vector_from_msg",
    "vector_to_msg",
    "yaw_from_msg",
    "yaw_to_msg",
]


def quaternion_from_msg(q: Quaternion) -> Quat:
    """``(x, y, z, w)`` of a Quaternion message."""
    return (q.x, q.y, q.z, q.w)


def quaternion_to_msg(q: Quat) -> Quaternion:
    """A Quaternion message from ``(x, y, z, w)``."""
    return Quaternion(x=q[0], y=q[1], z=q[2], w=q[3])


def yaw_from_msg(q: Quaternion) -> float:
    """The heading (rotation about Z) of a Quaternion message, in (-π, π]."""
    return yaw_from_quaternion((q.x, q.y, q.z, q.w))


def yaw_to_msg(yaw: float) -> Quaternion:
    """The Quaternion message of a rotation by ``yaw`` radians about Z."""
    return quaternion_to_msg(quaternion_from_yaw(yaw))


def vector_from_msg(v: Vector3 | Point) -> Vec3:
    """``(x, y, z)`` of a Vector3 or Point message."""
    return (v.x, v.y, v.z)


def vector_to_msg(v: Vec3) -> Vector3:
    """A Vector3 message from ``(x, y, z)``."""
    return Vector3(x=v[0], y=v[1], z=v[2])


def point_from_msg(p: Point) -> Vec3:
    """``(x, y, z)`` of a Point message."""
    return (p.x, p.y, p.z)


def point_to_msg(p: Vec3) -> Point:
    """A Point message from ``(x, y, z)``."""
    return Point(x=p[0], y=p[1], z=p[2])


def transform_from_msg(t: Transform | TransformStamped) -> Tf:
    """The 7-tuple ``(x, y, z, qx, qy, qz, qw)`` of a Transform (or TransformStamped)."""
    tr = t.transform if isinstance(t, TransformStamped) else t
    v, q = tr.translation, tr.rotation
    return (v.x, v.y, v.z, q.x, q.y, q.z, q.w)


def transform_to_msg(tf: Tf) -> Transform:
    """A Transform message from a 7-tuple."""
    return Transform(
        translation=Vector3(x=tf[0], y=tf[1], z=tf[2]),
        rotation=Quaternion(x=tf[3], y=tf[4], z=tf[5], w=tf[6]),
    )


def transform_stamped(
    parent: str, child: str, tf: Tf, stamp: Time | None = None
) -> TransformStamped:
    """A TransformStamped for the link ``parent → child`` (i.e. ``T_parent_child``)."""
    return TransformStamped(
        header=Header(stamp=stamp if stamp is not None else Time(), frame_id=parent),
        child_frame_id=child,
        transform=transform_to_msg(tf),
    )


def pose_from_msg(p: Pose) -> tuple[Vec3, Quat]:
    """``((x, y, z), (qx, qy, qz, qw))`` of a Pose message."""
    o = p.orientation
    return (p.position.x, p.position.y, p.position.z), (o.x, o.y, o.z, o.w)


def pose_to_msg(position: Vec3, orientation: Quat) -> Pose:
    """A Pose message from a position and an orientation."""
    return Pose(position=point_to_msg(position), orientation=quaternion_to_msg(orientation))


def pose_to_transform(p: Pose) -> Tf:
    """The transform that maps the pose's frame to its parent (same seven numbers)."""
    o = p.orientation
    return (p.position.x, p.position.y, p.position.z, o.x, o.y, o.z, o.w)


def transform_to_pose(tf: Tf) -> Pose:
    """The pose whose position and orientation are the transform's (same seven numbers)."""
    return pose_to_msg((tf[0], tf[1], tf[2]), (tf[3], tf[4], tf[5], tf[6]))


def matrix_from_msg(t: Transform | TransformStamped | Pose) -> Array:
    """The 4x4 homogeneous matrix of a Transform, TransformStamped or Pose message."""
    if isinstance(t, Pose):
        return transform_matrix(pose_to_transform(t))
    return transform_matrix(transform_from_msg(t))


def msg_from_matrix(m: Array) -> Transform:
    """A Transform message from a 4x4 homogeneous matrix."""
    return transform_to_msg(transform_from_matrix(m))
