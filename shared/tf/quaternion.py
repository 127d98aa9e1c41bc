"""Quaternions and angles on plain floats: products, slerp, axis-angle and Euler RPY.

Quaternions are ``(x, y, z, w)`` tuples in ROS order, Hamilton convention. Plain floats
beat numpy by an order of magnitude on single quaternions, so the TF buffer's hot path
uses the same formulas (inlined); numpy versions for arrays live in ``matrix``.
"""

from __future__ import annotations

import math

from ..errors import InvalidArgumentException

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]

IDENTITY_QUATERNION: Quat = (0.0, 0.0, 0.0, 1.0)

__all__ = [
    "IDENTITY_QUATERNION",
    "Quat",
    "Vec3",
    "angle_between",
    "euler_from_quaternion",
    "normalize_angle",
    "normalize_angle_positive",
    "quaternion_angle",
    "quaternion_conjugate",
    "quaternion_from_axis_angle",
    "quaternion_from_euler",
    "quaternion_from_yaw",
    "quaternion_inverse",
    "quaternion_multiply",
    "quaternion_norm",
    "quaternion_normalize",
    "quaternion_slerp",
    "quaternion_to_axis_angle",
    "rotate_vector",
    "shortest_angular_distance",
    "yaw_from_quaternion",
]


def quaternion_multiply(a: Quat, b: Quat) -> Quat:
    """The Hamilton product ``a * b`` (apply ``b`` first, then ``a``)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def quaternion_conjugate(q: Quat) -> Quat:
    """The conjugate; for a unit quaternion this is its inverse."""
    return (-q[0], -q[1], -q[2], q[3])


def quaternion_norm(q: Quat) -> float:
    """The Euclidean length of ``q``."""
    return math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])


def quaternion_inverse(q: Quat) -> Quat:
    """The inverse ``q⁻¹`` (conjugate over squared norm), for unit and non-unit quaternions.

    Raises:
        InvalidArgumentException: ``q`` is zero or not finite.
    """
    n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
    if not (n2 > 0.0 and math.isfinite(n2)):
        raise InvalidArgumentException(f"cannot invert quaternion {q}: expected a non-zero norm")
    return (-q[0] / n2, -q[1] / n2, -q[2] / n2, q[3] / n2)


def quaternion_normalize(q: Quat) -> Quat:
    """``q`` scaled to unit length.

    Raises:
        InvalidArgumentException: ``q`` is zero or not finite.
    """
    n = quaternion_norm(q)
    if not (n > 0.0 and math.isfinite(n)):
        raise InvalidArgumentException(f"cannot normalize quaternion {q}: expected a non-zero norm")
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def rotate_vector(q: Quat, v: Vec3) -> Vec3:
    """Rotate ``v`` by the unit quaternion ``q`` (``q v q*``)."""
    qx, qy, qz, qw = q
    vx, vy, vz = v
    tx = 2.0 * (qy * vz - qz * vy)
    ty = 2.0 * (qz * vx - qx * vz)
    tz = 2.0 * (qx * vy - qy * vx)
    return (
        vx + qw * tx + qy * tz - qz * ty,
        vy + qw * ty + qz * tx - qx * tz,
        vz + qw * tz + qx * ty - qy * tx,
    )


def quaternion_slerp(a: Quat, b: Quat, r: float) -> Quat:
    """Spherical interpolation from ``a`` (r = 0) to ``b`` (r = 1), exactly as tf2 does it.

    The short arc is always taken: if ``dot(a, b) < 0`` then ``-b`` is used. If the two
    rotations are equal (θ = 0), ``a`` is returned unchanged.
    """
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    d = ax * bx + ay * by + az * bz + aw * bw
    s = math.sqrt((ax * ax + ay * ay + az * az + aw * aw) * (bx * bx + by * by + bz * bz + bw * bw))
    theta = math.acos(max(-1.0, min(1.0, abs(d) / s)))
    if theta == 0.0:
        return a
    inv = 1.0 / math.sin(theta)
    s0 = math.sin((1.0 - r) * theta) * inv
    s1 = math.sin(r * theta) * inv
    if d < 0.0:
        s1 = -s1
    return (ax * s0 + bx * s1, ay * s0 + by * s1, az * s0 + bz * s1, aw * s0 + bw * s1)


def quaternion_angle(q: Quat) -> float:
    """The rotation angle of the unit quaternion ``q``, in [0, π]."""
    v = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2])
    return 2.0 * math.atan2(v, abs(q[3]))


def angle_between(a: Quat, b: Quat) -> float:
    """The angle of the shortest rotation taking ``a`` to ``b``, in [0, π]."""
    return quaternion_angle(quaternion_multiply(quaternion_conjugate(a), b))


def quaternion_from_axis_angle(axis: Vec3, angle: float) -> Quat:
    """The rotation by ``angle`` radians about ``axis`` (normalised here).

    Raises:
        InvalidArgumentException: ``axis`` is zero or not finite.
    """
    n = math.sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2])
    if not (n > 0.0 and math.isfinite(n)):
        raise InvalidArgumentException(f"rotation axis {axis} must be a non-zero finite vector")
    s = math.sin(angle / 2.0) / n
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2.0))


def quaternion_to_axis_angle(q: Quat) -> tuple[Vec3, float]:
    """``(unit axis, angle)`` of the unit quaternion ``q``, with the angle in [0, π].

    The identity gives the axis ``(1, 0, 0)`` and angle 0, as tf2's ``getAxis`` does.
    """
    x, y, z, w = q
    if w < 0.0:
        x, y, z, w = -x, -y, -z, -w
    v = math.sqrt(x * x + y * y + z * z)
    if v < 1e-15:
        return (1.0, 0.0, 0.0), 0.0
    return (x / v, y / v, z / v), 2.0 * math.atan2(v, w)


def quaternion_from_euler(roll: float, pitch: float, yaw: float) -> Quat:
    """The rotation for fixed-axis roll (X), pitch (Y), yaw (Z): ``R = Rz·Ry·Rx`` (tf2 setRPY)."""
    hr, hp, hy = roll * 0.5, pitch * 0.5, yaw * 0.5
    cr, sr = math.cos(hr), math.sin(hr)
    cp, sp = math.cos(hp), math.sin(hp)
    cy, sy = math.cos(hy), math.sin(hy)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def euler_from_quaternion(q: Quat) -> Vec3:
    """``(roll, pitch, yaw)`` of the unit quaternion ``q``, inverse of `quaternion_from_euler`.

    Pitch is in [-π/2, π/2]. At gimbal lock (|pitch| = π/2) yaw is set to 0 and the whole
    rotation about Z goes into roll, as tf2's ``Matrix3x3::getRPY`` does. "At" means within
    about 1e-7 rad: closer than that, roll and yaw cannot be told apart in float64.
    """
    x, y, z, w = q
    m20 = 2.0 * (x * z - w * y)
    if abs(m20) >= 1.0 - 1e-14:
        m01 = 2.0 * (x * y - w * z)
        m11 = 1.0 - 2.0 * (x * x + z * z)
        if m20 < 0.0:
            return math.atan2(m01, m11), math.pi / 2.0, 0.0
        return math.atan2(-m01, m11), -math.pi / 2.0, 0.0
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = -math.asin(m20)
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


def quaternion_from_yaw(yaw: float) -> Quat:
    """The rotation by ``yaw`` radians about Z (planar robots)."""
    return (0.0, 0.0, math.sin(yaw * 0.5), math.cos(yaw * 0.5))


def yaw_from_quaternion(q: Quat) -> float:
    """The heading (rotation about Z) of ``q``, in (-π, π]; tf2's ``getYaw``."""
    x, y, z, w = q
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def normalize_angle_positive(angle: float) -> float:
    """``angle`` wrapped into [0, 2π) (ROS ``angles::normalize_angle_positive``)."""
    tau = 2.0 * math.pi
    a = math.fmod(math.fmod(angle, tau) + tau, tau)
    return 0.0 if a == tau else a


def normalize_angle(angle: float) -> float:
    """``angle`` wrapped into (-π, π] (ROS ``angles::normalize_angle``)."""
    a = math.fmod(angle + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        return a + math.pi
    return a - math.pi


def shortest_angular_distance(from_angle: float, to_angle: float) -> float:
    """The signed smallest rotation taking ``from_angle`` to ``to_angle``, in (-π, π]."""
    return normalize_angle(to_angle - from_angle)
