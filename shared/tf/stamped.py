"""Applying a looked-up `TransformStamped` to stamped geometry (tf2_geometry_msgs' ``do_transform_*``).

Each function returns a new message in the transform's frame, with the transform's header
(its stamp and ``frame_id``), as tf2 does. Vectors are rotated only.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

from ..errors import InvalidArgumentException
from ..message import Float64Array
from ..msgs.geometry_msgs import (
    Point,
    PointStamped,
    Pose,
    PoseStamped,
    PoseWithCovariance,
    PoseWithCovarianceStamped,
    Quaternion,
    QuaternionStamped,
    TransformStamped,
    Vector3,
    Vector3Stamped,
)
from ..msgs.std_msgs import Header
from .convert import transform_from_msg
from .matrix import quaternion_matrix
from .rigid import transform_point, transform_pose, transform_quaternion, transform_vector

M = TypeVar("M")
Transformer = Callable[[Any, TransformStamped], Any]

__all__ = [
    "do_transform",
    "do_transform_point",
    "do_transform_pose",
    "do_transform_pose_stamped",
    "do_transform_pose_with_covariance_stamped",
    "do_transform_quaternion",
    "do_transform_vector3",
    "register_transformable",
    "transformable_types",
]


def _header(t: TransformStamped) -> Header:
    return Header(stamp=t.header.stamp, frame_id=t.header.frame_id)


def do_transform_point(p: PointStamped, t: TransformStamped) -> PointStamped:
    """The point in ``t``'s target frame."""
    x, y, z = transform_point(transform_from_msg(t), (p.point.x, p.point.y, p.point.z))
    return PointStamped(header=_header(t), point=Point(x=x, y=y, z=z))


def do_transform_vector3(v: Vector3Stamped, t: TransformStamped) -> Vector3Stamped:
    """The vector in ``t``'s target frame: rotated, not translated."""
    x, y, z = transform_vector(transform_from_msg(t), (v.vector.x, v.vector.y, v.vector.z))
    return Vector3Stamped(header=_header(t), vector=Vector3(x=x, y=y, z=z))


def do_transform_quaternion(q: QuaternionStamped, t: TransformStamped) -> QuaternionStamped:
    """The orientation in ``t``'s target frame."""
    o = q.quaternion
    x, y, z, w = transform_quaternion(transform_from_msg(t), (o.x, o.y, o.z, o.w))
    return QuaternionStamped(header=_header(t), quaternion=Quaternion(x=x, y=y, z=z, w=w))


def do_transform_pose(p: Pose, t: TransformStamped) -> Pose:
    """An unstamped pose in ``t``'s target frame."""
    o = p.orientation
    (x, y, z), (qx, qy, qz, qw) = transform_pose(
        transform_from_msg(t), ((p.position.x, p.position.y, p.position.z), (o.x, o.y, o.z, o.w))
    )
    return Pose(position=Point(x=x, y=y, z=z), orientation=Quaternion(x=qx, y=qy, z=qz, w=qw))


def do_transform_pose_stamped(p: PoseStamped, t: TransformStamped) -> PoseStamped:
    """The pose in ``t``'s target frame."""
    return PoseStamped(header=_header(t), pose=do_transform_pose(p.pose, t))


def do_transform_pose_with_covariance_stamped(
    p: PoseWithCovarianceStamped, t: TransformStamped
) -> PoseWithCovarianceStamped:
    """The pose in ``t``'s target frame, with its 6x6 covariance rotated (``R·C·Rᵀ`` per block)."""
    q = t.transform.rotation
    r6 = np.zeros((6, 6))
    r6[:3, :3] = r6[3:, 3:] = quaternion_matrix((q.x, q.y, q.z, q.w))
    cov = np.asarray(p.pose.covariance, dtype=np.float64).reshape(6, 6)
    out = PoseWithCovariance(pose=do_transform_pose(p.pose.pose, t))
    out.covariance = np.ascontiguousarray((r6 @ cov @ r6.T).reshape(36)).view(Float64Array)
    return PoseWithCovarianceStamped(header=_header(t), pose=out)


_REGISTRY: dict[type, tuple[Transformer, Callable[[Any], Header]]] = {}


def register_transformable(
    cls: type[M], fn: Callable[[M, TransformStamped], M], header: Callable[[M], Header]
) -> None:
    """Teach `Buffer.transform` a new stamped type: how to apply, and where its header is."""
    _REGISTRY[cls] = (fn, header)


def transformable_types() -> list[str]:
    """Names of the types `Buffer.transform` accepts."""
    return sorted(c.__name__ for c in _REGISTRY)


def _lookup_entry(obj: object) -> tuple[Transformer, Callable[[Any], Header]]:
    entry = _REGISTRY.get(type(obj))
    if entry is None:
        raise InvalidArgumentException(
            f"cannot transform a {type(obj).__name__}; supported types are "
            + ", ".join(transformable_types())
        )
    return entry


def header_of(obj: object) -> Header:
    """The header of a transformable message (its frame and stamp)."""
    return _lookup_entry(obj)[1](obj)


def do_transform(obj: M, t: TransformStamped) -> M:
    """Apply ``t`` to any registered stamped type.

    Raises:
        InvalidArgumentException: the type is not registered.
    """
    result: M = _lookup_entry(obj)[0](obj, t)
    return result


def _h(m: Any) -> Header:
    h: Header = m.header
    return h


for _cls, _fn in (
    (PointStamped, do_transform_point),
    (Vector3Stamped, do_transform_vector3),
    (QuaternionStamped, do_transform_quaternion),
    (PoseStamped, do_transform_pose_stamped),
    (PoseWithCovarianceStamped, do_transform_pose_with_covariance_stamped),
):
    _REGISTRY[_cls] = (_fn, _h)
