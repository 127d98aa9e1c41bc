"""Buffer.transform on stamped geometry, static runs inside chains, and the walk's loop guard."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.errors import InvalidArgumentException, LookupException
from zenros.message import Float64Array
from zenros.msgs.geometry_msgs import (
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
from zenros.msgs.std_msgs import Header
from zenros.tf import (
    Buffer,
    do_transform,
    quaternion_from_yaw,
    register_transformable,
    yaw_from_quaternion,
)
from zenros.tf.cache import StaticCache
from zenros.tf.stamped import _REGISTRY
from zenros.tf.walk import latest_common_time, walk
from tf_links import T, link

@pytest.fixture
def buf() -> Buffer:
    b = Buffer()
    # map -> base: base at (1, 0) facing +y at t = 1, at (3, 0) at t = 3
    b.set_transform(link("map", "base", 1.0, x=1.0, yaw=math.pi / 2), "me")
    b.set_transform(link("map", "base", 3.0, x=3.0, yaw=math.pi / 2), "me")
    return b


def test_point(buf: Buffer) -> None:
    p = PointStamped(header=Header(stamp=T(2.0), frame_id="base"), point=Point(x=1.0))
    out = buf.transform(p, "map")
    assert out.header.frame_id == "map" and out.header.stamp == T(2.0)
    assert (out.point.x, out.point.y, out.point.z) == pytest.approx((2.0, 1.0, 0.0))


def test_vector_is_only_rotated(buf: Buffer) -> None:
    v = Vector3Stamped(header=Header(stamp=T(2.0), frame_id="base"), vector=Vector3(x=1.0))
    out = buf.transform(v, "map")
    assert (out.vector.x, out.vector.y, out.vector.z) == pytest.approx((0.0, 1.0, 0.0))


def test_pose_and_quaternion(buf: Buffer) -> None:
    q = quaternion_from_yaw(0.25)
    pose = PoseStamped(
        header=Header(stamp=T(1.0), frame_id="base"),
        pose=Pose(position=Point(x=1.0), orientation=Quaternion(x=q[0], y=q[1], z=q[2], w=q[3])),
    )
    out = buf.transform(pose, "map")
    o = out.pose.orientation
    assert (out.pose.position.x, out.pose.position.y) == pytest.approx((1.0, 1.0))
    assert yaw_from_quaternion((o.x, o.y, o.z, o.w)) == pytest.approx(math.pi / 2 + 0.25)
    qs = QuaternionStamped(header=pose.header, quaternion=pose.pose.orientation)
    o = buf.transform(qs, "map").quaternion
    assert yaw_from_quaternion((o.x, o.y, o.z, o.w)) == pytest.approx(math.pi / 2 + 0.25)


def test_pose_with_covariance_rotates_the_covariance(buf: Buffer) -> None:
    cov = np.zeros((6, 6))
    cov[0, 0] = 4.0  # variance along base x
    msg = PoseWithCovarianceStamped(
        header=Header(stamp=T(1.0), frame_id="base"),
        pose=PoseWithCovariance(),
    )
    msg.pose.covariance = np.ascontiguousarray(cov.reshape(36)).view(Float64Array)
    out = buf.transform(msg, "map")
    c = np.asarray(out.pose.covariance).reshape(6, 6)
    assert c[1, 1] == pytest.approx(4.0) and c[0, 0] == pytest.approx(0.0, abs=1e-12)
    assert isinstance(out.pose.covariance, Float64Array)


def test_time_travel_transform(buf: Buffer) -> None:
    buf.set_transform_static(link("world", "map", 0.0), "me")
    p = PointStamped(header=Header(stamp=T(1.0), frame_id="base"), point=Point())
    out = buf.transform_full(p, "base", T(3.0), "map")  # where base was at 1, seen at 3
    assert out.header.stamp == T(3.0)
    assert (out.point.x, out.point.y) == pytest.approx((0.0, 2.0))


def test_unknown_type_and_registration(buf: Buffer) -> None:
    with pytest.raises(InvalidArgumentException, match="cannot transform a Point; supported"):
        buf.transform(Point(), "map")

    def shift(h: Header, t: TransformStamped) -> Header:
        return Header(stamp=t.header.stamp, frame_id=t.header.frame_id)

    register_transformable(Header, shift, lambda h: h)
    try:
        out = buf.transform(Header(stamp=T(2.0), frame_id="base"), "map")
        assert out.frame_id == "map"
        assert do_transform(Header(), buf.lookup_transform("map", "base", T(2.0))).frame_id == "map"
    finally:
        _REGISTRY.pop(Header)


def test_static_runs_inside_a_chain() -> None:
    b = Buffer()
    b.set_transform_static(link("world", "map", 0.0, x=100.0), "s")
    b.set_transform(link("map", "odom", 1.0, x=1.0), "d")
    b.set_transform(link("map", "odom", 2.0, x=2.0), "d")
    b.set_transform_static(link("odom", "base", 0.0, y=1.0, yaw=math.pi / 2), "s")
    b.set_transform_static(link("base", "arm", 0.0, x=1.0), "s")
    b.set_transform(link("arm", "hand", 1.0, x=0.5), "d")
    b.set_transform(link("arm", "hand", 2.0, x=1.5), "d")
    b.set_transform_static(link("hand", "tool", 0.0, x=0.1), "s")
    out = b.lookup_transform("world", "tool", T(1.5))
    v = out.transform.translation
    # tool at x = 0.1 + 1.0 (hand) + 1 (arm) along base x, which points along world +y
    assert (v.x, v.y) == pytest.approx((101.5, 1.0 + 2.1))
    back = b.lookup_transform("tool", "world", T(1.5)).transform.translation
    assert (back.x, back.y) == pytest.approx((-3.1, 101.5))
    b.set_transform_static(link("base", "arm", 0.0, x=2.0), "s")  # a static change is seen
    assert b.lookup_transform("world", "tool", T(1.5)).transform.translation.y == pytest.approx(4.1)


def test_walk_reports_a_loop_with_the_frame_dump() -> None:
    caches = {
        "a": StaticCache("b", (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)),
        "b": StaticCache("a", (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)),
        "c": StaticCache("a", (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)),
        "d": StaticCache("e", (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)),
    }
    with pytest.raises(LookupException, match="contains a loop.\nFRAMES"):
        walk(caches, "d", "c", 1, len(caches) + 1, lambda: "FRAMES")
    with pytest.raises(LookupException, match="contains a loop"):
        latest_common_time(caches, "d", "c", len(caches) + 1, lambda: "FRAMES")
    # reaching the target before going round the loop still works (tf2's quirk)
    assert walk(caches, "a", "c", 1, len(caches) + 1, lambda: "") is not None
