"""Rotation (3x3) and homogeneous (4x4) matrices on numpy, and batch operations on points.

Use these for arrays (point clouds, trajectories); for one transform the plain-float
functions in ``rigid`` and ``quaternion`` are faster.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from ..errors import InvalidArgumentException
from .quaternion import Quat, Vec3, euler_from_quaternion, quaternion_from_euler
from .rigid import Tf

Array = npt.NDArray[np.float64]

__all__ = [
    "Array",
    "compose_matrices",
    "euler_from_matrix",
    "euler_matrix",
    "inverse_matrix",
    "quaternion_from_matrix",
    "quaternion_matrix",
    "quaternions_to_matrices",
    "transform_from_matrix",
    "transform_matrix",
    "transform_points",
    "transform_vectors",
]


def quaternion_matrix(q: Quat) -> Array:
    """The 3x3 rotation matrix of the unit quaternion ``q`` = (x, y, z, w)."""
    return quaternions_to_matrices(np.asarray(q, dtype=np.float64))


def quaternions_to_matrices(q: npt.ArrayLike) -> Array:
    """Rotation matrices for an array of unit quaternions: shape (..., 4) to (..., 3, 3)."""
    a = np.asarray(q, dtype=np.float64)
    x, y, z, w = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = w * x, w * y, w * z
    m = np.empty(a.shape[:-1] + (3, 3))
    m[..., 0, 0] = 1.0 - 2.0 * (yy + zz)
    m[..., 0, 1] = 2.0 * (xy - wz)
    m[..., 0, 2] = 2.0 * (xz + wy)
    m[..., 1, 0] = 2.0 * (xy + wz)
    m[..., 1, 1] = 1.0 - 2.0 * (xx + zz)
    m[..., 1, 2] = 2.0 * (yz - wx)
    m[..., 2, 0] = 2.0 * (xz - wy)
    m[..., 2, 1] = 2.0 * (yz + wx)
    m[..., 2, 2] = 1.0 - 2.0 * (xx + yy)
    return m


def quaternion_from_matrix(m: npt.ArrayLike) -> Quat:
    """The unit quaternion (with w ≥ 0) of a 3x3 rotation matrix or a 4x4 transform.

    Raises:
        InvalidArgumentException: the matrix is not 3x3 or 4x4.
    """
    a = np.asarray(m, dtype=np.float64)
    if a.shape not in ((3, 3), (4, 4)):
        raise InvalidArgumentException(f"expected a 3x3 or 4x4 matrix, got shape {a.shape}")
    r = a[:3, :3].tolist()
    (m00, m01, m02), (m10, m11, m12), (m20, m21, m22) = r
    tr = m00 + m11 + m22
    if tr > 0.0:
        s = math.sqrt(tr + 1.0) * 2.0
        q = ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    elif m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2.0
        q = (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    elif m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2.0
        q = ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    else:
        s = math.sqrt(1.0 + m22 - m00 - m11) * 2.0
        q = ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)
    n = math.sqrt(sum(c * c for c in q))
    sign = -1.0 if q[3] < 0.0 else 1.0
    return (q[0] * sign / n, q[1] * sign / n, q[2] * sign / n, q[3] * sign / n)


def euler_matrix(roll: float, pitch: float, yaw: float) -> Array:
    """The 3x3 rotation matrix ``Rz(yaw)·Ry(pitch)·Rx(roll)``."""
    return quaternion_matrix(quaternion_from_euler(roll, pitch, yaw))


def euler_from_matrix(m: npt.ArrayLike) -> Vec3:
    """``(roll, pitch, yaw)`` of a 3x3 rotation matrix or a 4x4 transform."""
    return euler_from_quaternion(quaternion_from_matrix(m))


def transform_matrix(tf: Tf) -> Array:
    """The 4x4 homogeneous matrix of a transform tuple ``(x, y, z, qx, qy, qz, qw)``."""
    m = np.eye(4)
    m[:3, :3] = quaternion_matrix((tf[3], tf[4], tf[5], tf[6]))
    m[:3, 3] = tf[:3]
    return m


def transform_from_matrix(m: npt.ArrayLike) -> Tf:
    """The transform tuple of a 4x4 homogeneous matrix.

    Raises:
        InvalidArgumentException: the matrix is not 4x4.
    """
    a = np.asarray(m, dtype=np.float64)
    if a.shape != (4, 4):
        raise InvalidArgumentException(f"expected a 4x4 matrix, got shape {a.shape}")
    x, y, z = a[:3, 3].tolist()
    return (x, y, z, *quaternion_from_matrix(a))


def compose_matrices(*matrices: npt.ArrayLike) -> Array:
    """The product ``M1·M2·…·Mn`` of 4x4 (or 3x3) matrices, left to right."""
    if not matrices:
        raise InvalidArgumentException("compose_matrices needs at least one matrix")
    out = np.asarray(matrices[0], dtype=np.float64)
    for m in matrices[1:]:
        out = out @ np.asarray(m, dtype=np.float64)
    return out


def inverse_matrix(m: npt.ArrayLike) -> Array:
    """The inverse of a rigid 4x4 transform (transpose the rotation; no general inversion)."""
    a = np.asarray(m, dtype=np.float64)
    out = np.eye(4)
    rt = a[:3, :3].T
    out[:3, :3] = rt
    out[:3, 3] = -rt @ a[:3, 3]
    return out


def _as_points(points: npt.ArrayLike) -> Array:
    a = np.asarray(points, dtype=np.float64)
    if a.ndim == 0 or a.shape[-1] != 3:
        raise InvalidArgumentException(f"expected points of shape (..., 3), got {a.shape}")
    return a


def _as_matrix(tf: Tf | Sequence[float] | Array) -> Array:
    """A transform given as a 7-tuple or a 4x4 matrix, as a 4x4 matrix."""
    m = np.asarray(tf, dtype=np.float64)
    return m if m.shape == (4, 4) else transform_matrix(tuple(m.tolist()))


def transform_points(tf: Tf | Sequence[float] | Array, points: npt.ArrayLike) -> Array:
    """Apply a transform (7-tuple or 4x4 matrix) to points of shape (..., 3)."""
    p, m = _as_points(points), _as_matrix(tf)
    out: Array = p @ m[:3, :3].T + m[:3, 3]
    return out


def transform_vectors(tf: Tf | Sequence[float] | Array, vectors: npt.ArrayLike) -> Array:
    """Rotate free vectors of shape (..., 3) by a transform's rotation (no translation)."""
    out: Array = _as_points(vectors) @ _as_matrix(tf)[:3, :3].T
    return out
