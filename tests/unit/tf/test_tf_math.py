"""zenros.tf math: quaternions, angles, rigid transforms, matrices and message conversions."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from zenros.errors import InvalidArgumentException
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import Point, Pose, Quaternion, Transform, Vector3
from zenros.tf import (
    IDENTITY,
    angle_between,
    compose,
    euler_from_matrix,
    euler_from_quaternion,
    euler_matrix,
    interpolate,
    inverse,
    inverse_matrix,
    matrix_from_msg,
    msg_from_matrix,
    normalize_angle,
    normalize_angle_positive,
    pose_from_msg,
    pose_to_msg,
    quaternion_conjugate,
    quaternion_from_axis_angle,
    quaternion_from_euler,
    quaternion_from_matrix,
    quaternion_from_msg,
    quaternion_from_yaw,
    quaternion_inverse,
    quaternion_matrix,
    quaternion_multiply,
    quaternion_normalize,
    quaternion_slerp,
    quaternion_to_axis_angle,
    quaternion_to_msg,
    rotate_vector,
    shortest_angular_distance,
    transform_from_matrix,
    transform_from_msg,
    transform_matrix,
    transform_points,
    transform_stamped,
    transform_to_msg,
    transform_vectors,
    yaw_from_quaternion,
)
from zenros.tf.convert import (
    pose_to_transform,
    transform_to_pose,
    vector_from_msg,
    yaw_from_msg,
    yaw_to_msg,
)
from zenros.tf.rigid import (
    distance,
    rotation_distance,
    transform_point,
    transform_pose,
    transform_quaternion,
    transform_vector,
    translation_distance,
)

PI = math.pi


def approx(a: object, b: object, tol: float = 1e-9) -> bool:
    return bool(np.allclose(np.asarray(a, dtype=float), np.asarray(b, dtype=float), atol=tol))


def same_rotation(q1: tuple[float, ...], q2: tuple[float, ...], tol: float = 1e-9) -> bool:
    return approx(q1, q2, tol) or approx(q1, [-c for c in q2], tol)


def random_quaternion(rng: random.Random) -> tuple[float, float, float, float]:
    q = quaternion_normalize((rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
    return (float(q[0]), float(q[1]), float(q[2]), float(q[3]))


def random_tf(rng: random.Random) -> tuple[float, ...]:
    return (rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5), *random_quaternion(rng))


# ---------------------------------------------------------------- quaternions


def test_multiply_composes_rotations_hamilton_order() -> None:
    qz = quaternion_from_axis_angle((0, 0, 1), PI / 2)
    qx = quaternion_from_axis_angle((1, 0, 0), PI / 2)
    # apply qx first, then qz
    q = quaternion_multiply(qz, qx)
    assert approx(rotate_vector(q, (0, 1, 0)), rotate_vector(qz, rotate_vector(qx, (0, 1, 0))))
    assert approx(rotate_vector(q, (0, 1, 0)), (0, 0, 1))


def test_inverse_conjugate_and_normalize() -> None:
    q = quaternion_from_euler(0.3, -0.2, 1.1)
    assert approx(quaternion_multiply(q, quaternion_conjugate(q)), (0, 0, 0, 1))
    scaled = tuple(2.0 * c for c in q)
    assert approx(quaternion_multiply(scaled, quaternion_inverse(scaled)), (0, 0, 0, 1))
    assert approx(quaternion_normalize(scaled), q)
    with pytest.raises(InvalidArgumentException, match="non-zero"):
        quaternion_normalize((0.0, 0.0, 0.0, 0.0))
    with pytest.raises(InvalidArgumentException):
        quaternion_inverse((0.0, 0.0, 0.0, 0.0))


def test_rotate_vector_matches_matrix() -> None:
    rng = random.Random(3)
    for _ in range(50):
        q = random_quaternion(rng)
        v = (rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3))
        assert approx(rotate_vector(q, v), quaternion_matrix(q) @ np.array(v))


def test_axis_angle_round_trip_and_identity() -> None:
    q = quaternion_from_axis_angle((0, 2, 0), 0.7)  # axis gets normalised
    axis, angle = quaternion_to_axis_angle(q)
    assert approx(axis, (0, 1, 0)) and angle == pytest.approx(0.7)
    axis, angle = quaternion_to_axis_angle((0.0, 0.0, 0.0, 1.0))
    assert axis == (1.0, 0.0, 0.0) and angle == 0.0
    # angle comes back in [0, π] (sign folded into the axis)
    axis, angle = quaternion_to_axis_angle(quaternion_from_axis_angle((0, 0, 1), -0.5))
    assert approx(axis, (0, 0, -1)) and angle == pytest.approx(0.5)
    with pytest.raises(InvalidArgumentException, match="axis"):
        quaternion_from_axis_angle((0, 0, 0), 1.0)


def test_euler_matches_tf2_setrpy_convention() -> None:
    # fixed axes: R = Rz(yaw)·Ry(pitch)·Rx(roll)
    r, p, y = 0.1, 0.2, 0.3
    expected = (
        quaternion_matrix(quaternion_from_axis_angle((0, 0, 1), y))
        @ quaternion_matrix(quaternion_from_axis_angle((0, 1, 0), p))
        @ quaternion_matrix(quaternion_from_axis_angle((1, 0, 0), r))
    )
    assert approx(quaternion_matrix(quaternion_from_euler(r, p, y)), expected)
    assert approx(euler_matrix(r, p, y), expected)


def test_euler_round_trip() -> None:
    rng = random.Random(5)
    for _ in range(200):
        rpy = (rng.uniform(-PI, PI), rng.uniform(-PI / 2 + 1e-3, PI / 2 - 1e-3), rng.uniform(-PI, PI))
        assert approx(euler_from_quaternion(quaternion_from_euler(*rpy)), rpy, 1e-7)


@pytest.mark.parametrize("pitch", [PI / 2, -PI / 2])
def test_euler_gimbal_lock_gives_same_rotation(pitch: float) -> None:
    q = quaternion_from_euler(0.4, pitch, 0.9)
    r, p, y = euler_from_quaternion(q)
    assert p == pytest.approx(pitch, abs=1e-6)
    assert same_rotation(quaternion_from_euler(r, p, y), q, 1e-7)
    # exactly at the lock (|m20| = 1): yaw is 0 and roll carries the rotation about Z
    exact = quaternion_from_axis_angle((0, 1, 0), pitch)
    r, p, y = euler_from_quaternion(exact)
    assert (r, y) == (0.0, 0.0) and p == pytest.approx(pitch)


def test_yaw_helpers() -> None:
    assert yaw_from_quaternion(quaternion_from_yaw(2.5)) == pytest.approx(2.5)
    assert yaw_from_quaternion(quaternion_from_euler(0.0, 0.0, -3.0)) == pytest.approx(-3.0)


def test_yaw_message_helpers() -> None:
    q = yaw_to_msg(2.5)
    assert (q.x, q.y, q.z, q.w) == quaternion_from_yaw(2.5)
    assert yaw_from_msg(q) == yaw_from_quaternion((q.x, q.y, q.z, q.w)) == pytest.approx(2.5)
    assert yaw_from_msg(Quaternion()) == 0.0  # the identity
    assert yaw_from_msg(Quaternion(z=1.0, w=0.0)) == pytest.approx(math.pi)


def test_slerp_endpoints_midpoint_and_short_arc() -> None:
    a = quaternion_from_yaw(0.0)
    b = quaternion_from_yaw(1.0)
    assert approx(quaternion_slerp(a, b, 0.0), a)
    assert approx(quaternion_slerp(a, b, 1.0), b)
    assert yaw_from_quaternion(quaternion_slerp(a, b, 0.25)) == pytest.approx(0.25)
    # 170° to -170°: the short way goes through 180°, not through 0°
    q = quaternion_slerp(quaternion_from_yaw(math.radians(170)), quaternion_from_yaw(math.radians(-170)), 0.5)
    assert abs(yaw_from_quaternion(q)) == pytest.approx(PI)
    # the same rotation with opposite sign: stays put
    neg = tuple(-c for c in b)
    assert same_rotation(quaternion_slerp(b, neg, 0.3), b)
    # equal rotations (θ = 0): the first is returned as is
    assert quaternion_slerp(b, b, 0.5) == b


def test_angle_between_and_quaternion_angle() -> None:
    a = quaternion_from_yaw(0.2)
    b = quaternion_from_yaw(-0.3)
    assert angle_between(a, b) == pytest.approx(0.5)
    assert angle_between(a, tuple(-c for c in a)) == pytest.approx(0.0, abs=1e-7)


@pytest.mark.parametrize(
    ("angle", "expected"),
    [(0.0, 0.0), (PI, PI), (-PI, PI), (3 * PI / 2, -PI / 2), (-3 * PI / 2, PI / 2), (7.0, 7.0 - 2 * PI)],
)
def test_normalize_angle(angle: float, expected: float) -> None:
    assert normalize_angle(angle) == pytest.approx(expected)


def test_normalize_angle_positive_and_shortest_distance() -> None:
    assert normalize_angle_positive(-PI / 2) == pytest.approx(3 * PI / 2)
    assert normalize_angle_positive(2 * PI) == pytest.approx(0.0)
    assert shortest_angular_distance(math.radians(170), math.radians(-170)) == pytest.approx(math.radians(20))
    assert shortest_angular_distance(0.5, 0.2) == pytest.approx(-0.3)


# ---------------------------------------------------------------- rigid transforms


def test_compose_matches_matrix_product() -> None:
    rng = random.Random(7)
    for _ in range(50):
        a, b = random_tf(rng), random_tf(rng)
        got = transform_matrix(compose(a, b))
        assert approx(got, transform_matrix(a) @ transform_matrix(b))


def test_inverse_and_identity() -> None:
    rng = random.Random(9)
    a = random_tf(rng)
    c = compose(a, inverse(a))
    assert approx(c[:3], (0, 0, 0)) and same_rotation(c[3:], (0, 0, 0, 1))
    assert compose(IDENTITY, a) == pytest.approx(a)
    assert approx(transform_matrix(inverse(a)), np.linalg.inv(transform_matrix(a)))


def test_apply_to_points_vectors_poses_quaternions() -> None:
    t = (1.0, 2.0, 3.0, *quaternion_from_yaw(PI / 2))
    assert approx(transform_point(t, (1, 0, 0)), (1, 3, 3))
    assert approx(transform_vector(t, (1, 0, 0)), (0, 1, 0))  # rotation only
    q = transform_quaternion(t, quaternion_from_yaw(0.25))
    assert yaw_from_quaternion(q) == pytest.approx(PI / 2 + 0.25)
    (p, o) = transform_pose(t, ((1.0, 0.0, 0.0), quaternion_from_yaw(0.0)))
    assert approx(p, (1, 3, 3)) and yaw_from_quaternion(o) == pytest.approx(PI / 2)


def test_interpolate_is_linear_plus_slerp() -> None:
    a = (0.0, 0.0, 0.0, *quaternion_from_yaw(0.0))
    b = (2.0, -4.0, 6.0, *quaternion_from_yaw(1.0))
    m = interpolate(a, b, 0.25)
    assert approx(m[:3], (0.5, -1.0, 1.5))
    assert yaw_from_quaternion(m[3:]) == pytest.approx(0.25)


def test_distances() -> None:
    a = (0.0, 0.0, 0.0, *quaternion_from_yaw(0.0))
    b = (3.0, 4.0, 0.0, *quaternion_from_yaw(0.5))
    assert translation_distance(a, b) == pytest.approx(5.0)
    assert rotation_distance(a, b) == pytest.approx(0.5)
    assert distance((0, 0, 0), (1, 2, 2)) == pytest.approx(3.0)


# ---------------------------------------------------------------- matrices


def test_quaternion_from_matrix_all_branches() -> None:
    rng = random.Random(11)
    cases = [quaternion_from_axis_angle(ax, PI - 1e-3) for ax in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    cases += [random_quaternion(rng) for _ in range(100)]
    for q in cases:
        back = quaternion_from_matrix(quaternion_matrix(q))
        assert back[3] >= 0.0
        assert same_rotation(back, q, 1e-7)
    with pytest.raises(InvalidArgumentException, match="3x3 or 4x4"):
        quaternion_from_matrix(np.eye(2))


def test_transform_matrix_round_trip_and_inverse() -> None:
    rng = random.Random(13)
    t = random_tf(rng)
    m = transform_matrix(t)
    back = transform_from_matrix(m)
    assert approx(back[:3], t[:3]) and same_rotation(back[3:], t[3:])
    assert approx(inverse_matrix(m), np.linalg.inv(m))
    assert approx(euler_from_matrix(euler_matrix(0.1, 0.2, 0.3)), (0.1, 0.2, 0.3))
    with pytest.raises(InvalidArgumentException, match="4x4"):
        transform_from_matrix(np.eye(3))


def test_batch_points_and_vectors_match_single() -> None:
    rng = random.Random(17)
    t = random_tf(rng)
    pts = np.array([[rng.uniform(-2, 2) for _ in range(3)] for _ in range(20)])
    out = transform_points(t, pts)
    assert out.shape == (20, 3)
    for p, o in zip(pts, out, strict=True):
        assert approx(o, transform_point(t, tuple(p)))
    assert approx(transform_points(transform_matrix(t), pts), out)
    vec = transform_vectors(t, pts)
    assert approx(vec[0], transform_vector(t, tuple(pts[0])))
    with pytest.raises(InvalidArgumentException, match=r"\(\.\.\., 3\)"):
        transform_points(t, np.zeros((4, 2)))


# ---------------------------------------------------------------- messages


def test_message_conversions_round_trip() -> None:
    t = (1.0, 2.0, 3.0, *quaternion_from_yaw(0.5))
    msg = transform_to_msg(t)
    assert isinstance(msg, Transform) and transform_from_msg(msg) == t
    stamped = transform_stamped("map", "odom", t, Time(sec=4))
    assert stamped.header.frame_id == "map" and stamped.child_frame_id == "odom"
    assert stamped.header.stamp == Time(sec=4) and transform_from_msg(stamped) == t
    q = quaternion_to_msg(t[3:])
    assert isinstance(q, Quaternion) and quaternion_from_msg(q) == t[3:]
    pose = pose_to_msg((1.0, 2.0, 3.0), t[3:])
    assert pose_from_msg(pose) == ((1.0, 2.0, 3.0), t[3:])
    assert pose_to_transform(pose) == t and transform_to_pose(t) == pose
    assert vector_from_msg(Vector3(x=1.0, y=2.0, z=3.0)) == vector_from_msg(Point(x=1.0, y=2.0, z=3.0))
    assert approx(matrix_from_msg(msg), transform_matrix(t))
    assert approx(matrix_from_msg(Pose(position=Point(x=1.0, y=2.0, z=3.0), orientation=q)),
                  transform_matrix(t))  # fmt: skip
    assert approx(transform_from_msg(msg_from_matrix(transform_matrix(t))), t)
