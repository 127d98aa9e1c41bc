"""Rigid transforms on plain floats: ``(x, y, z, qx, qy, qz, qw)`` tuples.

A transform ``T_a_b`` maps coordinates given in frame ``b`` into frame ``a``:
``p_a = R(q)·p_b + t``. ``compose(T_a_b, T_b_c)`` is ``T_a_c``.
"""

from __future__ import annotations

import math

from .quaternion import Quat, Vec3, angle_between, quaternion_slerp

Tf = tuple[float, float, float, float, float, float, float]
Pose = tuple[Vec3, Quat]

IDENTITY: Tf = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)

__all__ = [
    "IDENTITY",
    "Pose",
    "Tf",
    "compose",
    "distance",
    "interpolate",
    "inverse",
    "rotation_distance",
    "transform_point",
    "transform_pose",
    "transform_quaternion",
    "transform_vector",
    "translation_distance",
]


def compose(a: Tf, b: Tf) -> Tf:
    """``a ∘ b``: apply ``b`` first, then ``a`` (``T_x_y ∘ T_y_z = T_x_z``)."""
    ax, ay, az, qx, qy, qz, qw = a
    bx, by, bz, rx, ry, rz, rw = b
    tx = 2.0 * (qy * bz - qz * by)
    ty = 2.0 * (qz * bx - qx * bz)
    tz = 2.0 * (qx * by - qy * bx)
    return (
        ax + bx + qw * tx + qy * tz - qz * ty,
        ay + by + qw * ty + qz * tx - qx * tz,
        az + bz + qw * tz + qx * ty - qy * tx,
        qw * rx + qx * rw + qy * rz - qz * ry,
        qw * ry - qx * rz + qy * rw + qz * rx,
        qw * rz + qx * ry - qy * rx + qz * rw,
        qw * rw - qx * rx - qy * ry - qz * rz,
    )


def inverse(a: Tf) -> Tf:
    """``a⁻¹``, so that ``compose(a, inverse(a))`` is the identity (unit quaternion assumed)."""
    x, y, z, qx, qy, qz, qw = a
    qx, qy, qz = -qx, -qy, -qz
    tx = 2.0 * (qy * z - qz * y)
    ty = 2.0 * (qz * x - qx * z)
    tz = 2.0 * (qx * y - qy * x)
    return (
        -(x + qw * tx + qy * tz - qz * ty),
        -(y + qw * ty + qz * tx - qx * tz),
        -(z + qw * tz + qx * ty - qy * tx),
        qx,
        qy,
        qz,
        qw,
    )


def transform_point(a: Tf, p: Vec3) -> Vec3:
    """The point ``p`` (coordinates in the source frame) in the target frame."""
    r = compose(a, (p[0], p[1], p[2], 0.0, 0.0, 0.0, 1.0))
    return (r[0], r[1], r[2])


def transform_vector(a: Tf, v: Vec3) -> Vec3:
    """The free vector ``v`` in the target frame: rotation only, no translation."""
    r = compose((0.0, 0.0, 0.0, a[3], a[4], a[5], a[6]), (v[0], v[1], v[2], 0.0, 0.0, 0.0, 1.0))
    return (r[0], r[1], r[2])


def transform_quaternion(a: Tf, q: Quat) -> Quat:
    """The orientation ``q`` in the target frame (``q_a·q``)."""
    r = compose((0.0, 0.0, 0.0, a[3], a[4], a[5], a[6]), (0.0, 0.0, 0.0, *q))
    return (r[3], r[4], r[5], r[6])


def transform_pose(a: Tf, pose: Pose) -> Pose:
    """The pose ``(position, orientation)`` in the target frame."""
    (px, py, pz), q = pose
    r = compose(a, (px, py, pz, *q))
    return (r[0], r[1], r[2]), (r[3], r[4], r[5], r[6])


def interpolate(a: Tf, b: Tf, r: float) -> Tf:
    """tf2's interpolation: linear in translation, short-arc slerp in rotation (r in [0, 1])."""
    s = 1.0 - r
    q = quaternion_slerp((a[3], a[4], a[5], a[6]), (b[3], b[4], b[5], b[6]), r)
    return (s * a[0] + r * b[0], s * a[1] + r * b[1], s * a[2] + r * b[2], *q)


def distance(p: Vec3, q: Vec3) -> float:
    """Euclidean distance between two points."""
    return math.dist(p, q)


def translation_distance(a: Tf, b: Tf) -> float:
    """Euclidean distance between the translations of two transforms."""
    return math.dist(a[:3], b[:3])


def rotation_distance(a: Tf, b: Tf) -> float:
    """The angle (radians, in [0, π]) of the rotation between two transforms."""
    return angle_between((a[3], a[4], a[5], a[6]), (b[3], b[4], b[5], b[6]))
