"""Buffer semantics against tf2 (specs/tf-nav.md Part A): inserts, caches, lookups, statics."""

from __future__ import annotations

import logging
import math

import pytest
from zenros.errors import (
    BackwardExtrapolationException,
    ConnectivityException,
    ExtrapolationException,
    ForwardExtrapolationException,
    InvalidArgumentException,
    LookupException,
    NoDataForExtrapolationException,
    TransformException,
)
from zenros.msgs.builtin_interfaces import Duration, Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.tf import (
    LATEST,
    Buffer,
    quaternion_from_yaw,
    yaw_from_quaternion,
)
from tf_links import NS, T, link

def xyz(msg: TransformStamped) -> tuple[float, float, float]:
    v = msg.transform.translation
    return (v.x, v.y, v.z)


def yaw(msg: TransformStamped) -> float:
    q = msg.transform.rotation
    return float(yaw_from_quaternion((q.x, q.y, q.z, q.w)))


@pytest.fixture
def buf() -> Buffer:
    return Buffer()


# ---------------------------------------------------------------- A1 conventions


def test_lookup_returns_target_from_source(buf: Buffer) -> None:
    assert buf.set_transform(link("map", "robot", 1.0, x=1.0, yaw=math.pi / 2), "test")
    t = buf.lookup_transform("map", "robot", T(1.0))
    assert t.header.frame_id == "map" and t.child_frame_id == "robot"
    assert t.header.stamp == T(1.0)
    assert xyz(t) == pytest.approx((1.0, 0.0, 0.0)) and yaw(t) == pytest.approx(math.pi / 2)
    back = buf.lookup_transform("robot", "map", T(1.0))
    assert xyz(back) == pytest.approx((0.0, 1.0, 0.0)) and yaw(back) == pytest.approx(-math.pi / 2)


# ---------------------------------------------------------------- A2 inserting


def test_one_leading_slash_is_stripped(buf: Buffer) -> None:
    assert buf.set_transform(link("/world", "/robot", 1.0), "test")
    assert buf.frame_exists("world") and buf.frame_exists("robot")
    assert not buf.frame_exists("/world")
    assert buf.can_transform("world", "robot", T(1.0))
    assert buf.set_transform(link("//world", "a", 1.0), "test")  # only one slash goes
    assert buf.frame_exists("/world")


@pytest.mark.parametrize(
    ("msg", "code"),
    [
        (link("a", "a", 1.0), "TF_SELF_TRANSFORM"),
        (link("/a", "a", 1.0), "TF_SELF_TRANSFORM"),
        (link("a", "", 1.0), "TF_NO_CHILD_FRAME_ID"),
        (link("", "b", 1.0), "TF_NO_FRAME_ID"),
        (link("/", "b", 1.0), "TF_NO_FRAME_ID"),
        (link("a", "b", 1.0, x=math.nan), "TF_NAN_INPUT"),
        (link("a", "b", 1.0, z=math.inf), "TF_NAN_INPUT"),
        (link("a", "b", 1.0, q=(0.0, 0.0, 0.0, math.nan)), "TF_NAN_INPUT"),
        (link("a", "b", 1.0, q=(0.0, 0.0, 0.0, 1.1)), "TF_DENORMALIZED_QUATERNION"),
        (link("a", "b", 1.0, q=(0.0, 0.0, 0.0, 0.0)), "TF_DENORMALIZED_QUATERNION"),
    ],
)
def test_invalid_inserts_are_refused(
    buf: Buffer, msg: TransformStamped, code: str, caplog: pytest.LogCaptureFixture
) -> None:
    with caplog.at_level(logging.WARNING, logger="zenros.tf"):
        assert buf.set_transform(msg, "me") is False
    assert code in caplog.text and '"me"' in caplog.text
    assert buf.get_frame_names() == []  # nothing registered
    with pytest.raises(InvalidArgumentException, match=code):
        buf.set_transform(msg, "me", strict=True)
    assert buf.set_transform_static(msg, "me") is False


def test_every_problem_is_reported(buf: Buffer, caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.WARNING, logger="zenros.tf"):
        assert not buf.set_transform(link("a", "a", 1.0, x=math.nan), "me")
    assert "TF_SELF_TRANSFORM" in caplog.text and "TF_NAN_INPUT" in caplog.text


def test_quaternion_tolerance_is_on_the_squared_norm(buf: Buffer) -> None:
    # |n² - 1| < 0.01 passes (ROS 1 rule) and is stored normalised
    assert buf.set_transform(link("a", "b", 1.0, q=(0.0, 0.0, 0.0, 1.004)), "me")
    assert not buf.set_transform(link("a", "c", 1.0, q=(0.0, 0.0, 0.0, 1.006)), "me")
    q = buf.lookup_transform("a", "b", T(1.0)).transform.rotation
    assert (q.x, q.y, q.z, q.w) == pytest.approx((0.0, 0.0, 0.0, 1.0))


def test_both_frames_registered_and_authority_kept(buf: Buffer) -> None:
    buf.set_transform(link("map", "odom", 1.0), "first")
    assert buf.frame_exists("map") and buf.frame_exists("odom")
    assert buf.get_frame_names() == ["odom", "map"]
    buf.set_transform(link("map", "odom", 2.0), "second")
    assert "broadcaster: 'second'" in buf.all_frames_as_yaml()


def test_cache_type_change_replaces_the_cache(buf: Buffer) -> None:
    buf.set_transform_static(link("a", "b", 0.0, x=1.0), "s")
    assert buf.can_transform("a", "b", T(50.0))
    buf.set_transform(link("a", "b", 5.0, x=2.0), "d")  # ROS 2: now a dynamic link
    assert not buf.can_transform("a", "b", T(50.0))
    assert xyz(buf.lookup_transform("a", "b", T(5.0)))[0] == pytest.approx(2.0)
    buf.set_transform_static(link("a", "b", 0.0, x=3.0), "s")  # and back
    assert xyz(buf.lookup_transform("a", "b", T(50.0)))[0] == pytest.approx(3.0)


# ---------------------------------------------------------------- A3 the time cache


def test_out_of_order_inserts_interpolate(buf: Buffer) -> None:
    for t, x in ((3.0, 3.0), (1.0, 1.0), (2.0, 2.0)):
        assert buf.set_transform(link("a", "b", t, x=x), "me")
    for t in (1.0, 1.5, 2.0, 2.25, 3.0):
        assert xyz(buf.lookup_transform("a", "b", T(t)))[0] == pytest.approx(t)


def test_same_stamp_replaces(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0, x=1.0), "me")
    buf.set_transform(link("a", "b", 2.0, x=2.0), "me")
    buf.set_transform(link("a", "b", 1.0, x=5.0), "me")
    assert xyz(buf.lookup_transform("a", "b", T(1.0)))[0] == pytest.approx(5.0)
    assert xyz(buf.lookup_transform("a", "b", T(1.5)))[0] == pytest.approx(3.5)
    assert "rate: 2.000" in buf.all_frames_as_yaml()  # still two samples


def test_too_old_is_refused_boundary_inclusive(caplog: pytest.LogCaptureFixture) -> None:
    buf = Buffer(cache_time=10.0)
    buf.set_transform(link("a", "b", 20.0), "me")
    assert buf.set_transform(link("a", "b", 10.0), "me")  # latest - cache_time: accepted
    with caplog.at_level(logging.WARNING, logger="zenros.tf"):
        assert not buf.set_transform(link("a", "b", 9.999), "me")
    assert "TF_OLD_DATA" in caplog.text
    with pytest.raises(InvalidArgumentException, match="TF_OLD_DATA"):
        buf.set_transform(link("a", "b", 9.0), "me", strict=True)


def test_pruning_after_insert_is_strict() -> None:
    buf = Buffer(cache_time=Duration(sec=10))
    buf.set_transform(link("a", "b", 1.0), "me")
    buf.set_transform(link("a", "b", 5.0), "me")
    buf.set_transform(link("a", "b", 11.0), "me")  # 1 + 10 == 11: not older, kept
    assert buf.can_transform("a", "b", T(1.0))
    buf.set_transform(link("a", "b", 11.5), "me")  # now 1 < 1.5: pruned at once (ROS 1)
    assert not buf.can_transform("a", "b", T(1.0))
    with pytest.raises(BackwardExtrapolationException, match="earliest data is at time 5.0"):
        buf.lookup_transform("a", "b", T(2.0))


def test_window_holds_many_samples_and_inserts_stay_cheap() -> None:
    buf = Buffer(cache_time=10.0)
    for k in range(30_000):  # 300 s at 100 Hz: every insert prunes one
        assert buf.set_transform(link("a", "b", k / 100.0, x=k / 100.0), "me")
    yml = buf.all_frames_as_yaml()
    assert "buffer_length: 10.000" in yml and "oldest_transform: 289.990" in yml
    assert xyz(buf.lookup_transform("a", "b", T(295.005)))[0] == pytest.approx(295.005)


# ---------------------------------------------------------------- A4 reading one link


def test_latest_returns_newest_with_its_stamp(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0, x=1.0), "me")
    buf.set_transform(link("a", "b", 2.0, x=2.0), "me")
    t = buf.lookup_transform("a", "b", LATEST)
    assert t.header.stamp == T(2.0) and xyz(t)[0] == 2.0
    assert buf.lookup_transform("a", "b", 0).header.stamp == T(2.0)


def test_single_sample_only_at_its_stamp(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0, x=1.0), "me")
    assert xyz(buf.lookup_transform("a", "b", T(1.0)))[0] == 1.0
    with pytest.raises(NoDataForExtrapolationException) as e:
        buf.lookup_transform("a", "b", T(2.0))
    assert str(e.value) == (
        "Lookup would require extrapolation at time 2.000000000, but only time 1.000000000 is "
        "in the buffer, when looking up transform from frame [b] to frame [a]"
    )


def test_exact_ends_and_extrapolation_both_ways(buf: Buffer) -> None:
    for t in (1.0, 2.0, 3.0):
        buf.set_transform(link("a", "b", t, x=t), "me")
    assert xyz(buf.lookup_transform("a", "b", T(1.0)))[0] == 1.0
    assert xyz(buf.lookup_transform("a", "b", T(3.0)))[0] == 3.0
    with pytest.raises(ForwardExtrapolationException) as fwd:
        buf.lookup_transform("a", "b", T(3.5))
    assert str(fwd.value) == (
        "Lookup would require extrapolation into the future.  Requested time 3.500000000 but "
        "the latest data is at time 3.000000000, when looking up transform from frame [b] to "
        "frame [a]"
    )
    with pytest.raises(BackwardExtrapolationException) as back:
        buf.lookup_transform("b", "a", T(0.5))
    assert "into the past.  Requested time 0.500000000 but the earliest data is at time " \
        "1.000000000, when looking up transform from frame [a] to frame [b]" in str(back.value)
    for exc in (fwd.value, back.value):
        assert isinstance(exc, ExtrapolationException) and isinstance(exc, TransformException)


def test_no_extrapolation_even_one_nanosecond(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0), "me")
    buf.set_transform(link("a", "b", 2.0), "me")
    assert buf.can_transform("a", "b", 2 * NS)
    assert not buf.can_transform("a", "b", 2 * NS + 1)
    assert not buf.can_transform("a", "b", NS - 1)


def test_interpolation_linear_and_slerp(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0, x=0.0, y=2.0, yaw=0.2), "me")
    buf.set_transform(link("a", "b", 3.0, x=4.0, y=-2.0, yaw=1.0), "me")
    t = buf.lookup_transform("a", "b", T(1.5))
    assert xyz(t) == pytest.approx((1.0, 1.0, 0.0)) and yaw(t) == pytest.approx(0.4)


def test_slerp_takes_the_short_arc(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0, yaw=math.radians(170)), "me")
    buf.set_transform(link("a", "b", 2.0, yaw=math.radians(-170)), "me")
    assert abs(yaw(buf.lookup_transform("a", "b", T(1.5)))) == pytest.approx(math.pi)
    q = quaternion_from_yaw(0.5)
    buf.set_transform(link("a", "c", 1.0, q=q), "me")
    buf.set_transform(link("a", "c", 2.0, q=tuple(-c for c in q)), "me")
    assert yaw(buf.lookup_transform("a", "c", T(1.3))) == pytest.approx(0.5)


def test_reparenting_is_never_interpolated(buf: Buffer) -> None:
    buf.set_transform(link("root", "p1", 0.0), "me")
    buf.set_transform(link("root", "p2", 0.0, x=10.0), "me")
    buf.set_transform_static(link("root", "p1", 0.0), "me")
    buf.set_transform_static(link("root", "p2", 0.0, x=10.0), "me")
    buf.set_transform(link("p1", "c", 1.0, x=1.0), "me")
    buf.set_transform(link("p2", "c", 2.0, x=2.0), "me")
    # between the two samples the older one is used as it is, with its parent
    assert buf.get_parent("c", T(1.5)) == "p1" and buf.get_parent("c", T(2.0)) == "p2"
    assert xyz(buf.lookup_transform("root", "c", T(1.5)))[0] == pytest.approx(1.0)
    assert xyz(buf.lookup_transform("root", "c", T(2.0)))[0] == pytest.approx(12.0)
    assert xyz(buf.lookup_transform("p1", "c", T(1.5)))[0] == pytest.approx(1.0)
    assert xyz(buf.lookup_transform("p2", "c", T(2.0)))[0] == pytest.approx(2.0)
    assert xyz(buf.lookup_transform("p2", "c", T(1.5)))[0] == pytest.approx(-9.0)  # via root


# ---------------------------------------------------------------- A5 static links


def test_static_valid_at_any_time_with_query_stamp(buf: Buffer) -> None:
    buf.set_transform_static(link("base", "laser", 123.0, x=0.2), "urdf")
    for t in (T(0.5), T(1e6), LATEST):
        out = buf.lookup_transform("base", "laser", t)
        assert xyz(out)[0] == pytest.approx(0.2) and out.header.stamp == t
    buf.set_transform_static(link("base", "laser", 1.0, x=0.3), "urdf")  # overwrite
    assert xyz(buf.lookup_transform("base", "laser", T(7.0)))[0] == pytest.approx(0.3)


def test_statics_do_not_hold_back_latest_and_survive_clear(buf: Buffer) -> None:
    buf.set_transform(link("odom", "base", 4.0, x=1.0), "odom")
    buf.set_transform(link("odom", "base", 5.0, x=2.0), "odom")
    buf.set_transform_static(link("base", "laser", 0.0, x=0.5), "urdf")
    out = buf.lookup_transform("odom", "laser", LATEST)
    assert out.header.stamp == T(5.0) and xyz(out)[0] == pytest.approx(2.5)
    buf.clear()
    assert buf.can_transform("base", "laser", T(99.0))
    assert not buf.can_transform("odom", "base", T(5.0))
    assert buf.frame_exists("odom")
    # a cleared dynamic link: time 0 reports connectivity (tf2's walk stops there)
    with pytest.raises(ConnectivityException):
        buf.lookup_transform("odom", "laser", LATEST)
    with pytest.raises(NoDataForExtrapolationException, match="only time 0.000000000"):
        buf.lookup_transform("odom", "laser", T(5.0))


def test_all_static_path_at_time_zero_is_stamped_zero(buf: Buffer) -> None:
    buf.set_transform_static(link("a", "b", 3.0, x=1.0), "s")
    buf.set_transform_static(link("b", "c", 3.0, x=1.0), "s")
    out = buf.lookup_transform("a", "c", LATEST)
    assert out.header.stamp == Time() and xyz(out)[0] == pytest.approx(2.0)
    assert buf.get_latest_common_time("a", "c") == Time()


# ---------------------------------------------------------------- A6 latest common time


def test_latest_common_time_skips_the_common_ancestors_own_link(buf: Buffer) -> None:
    for t in (1.0, 2.0):
        buf.set_transform(link("pp", "parent", t), "me")
    for t in (1.0, 2.0, 3.0):
        buf.set_transform(link("parent", "a", t), "me")
    for t in (1.0, 2.0, 3.0, 4.0):
        buf.set_transform(link("parent", "b", t, x=t), "me")
    assert buf.get_latest_common_time("a", "b") == T(3.0)
    out = buf.lookup_transform("a", "b", LATEST)  # parent -> pp has no data at 3: no matter
    assert out.header.stamp == T(3.0) and xyz(out)[0] == pytest.approx(3.0)
    assert buf.get_latest_common_time("pp", "b") == T(2.0)  # target is an ancestor
    assert buf.get_latest_common_time("b", "pp") == T(2.0)  # source is an ancestor
    assert buf.get_latest_common_time("b", "b") == T(4.0)


def test_latest_common_time_is_the_oldest_newest(buf: Buffer) -> None:
    for t in (1.0, 2.0, 3.0):
        buf.set_transform(link("root", "a", t, x=t), "me")
    for t in (1.0, 2.0):
        buf.set_transform(link("a", "b", t, y=t), "me")
    out = buf.lookup_transform("root", "b", LATEST)
    assert out.header.stamp == T(2.0) and xyz(out) == pytest.approx((2.0, 2.0, 0.0))


def test_unconnected_trees(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0), "me")
    buf.set_transform(link("c", "d", 1.0), "me")
    msg = ("Could not find a connection between 'a' and 'd' because they are not part of the "
           "same tree.Tf has two or more unconnected trees.")  # fmt: skip
    for t in (T(1.0), LATEST):
        with pytest.raises(ConnectivityException) as e:
            buf.lookup_transform("a", "d", t)
        assert str(e.value) == msg
    with pytest.raises(ConnectivityException):
        buf.get_latest_common_time("a", "d")


# ---------------------------------------------------------------- A7/A8 walking, identity


def test_identity_never_fails(buf: Buffer) -> None:
    out = buf.lookup_transform("nowhere", "nowhere", T(3.0))
    assert out.header.stamp == T(3.0) and xyz(out) == (0.0, 0.0, 0.0)
    assert buf.lookup_transform("", "", LATEST).header.stamp == Time()
    assert buf.can_transform("nowhere", "nowhere", T(1.0))
    buf.set_transform(link("a", "b", 7.0), "me")
    assert buf.lookup_transform("b", "b", LATEST).header.stamp == T(7.0)
    assert buf.lookup_transform("a", "a", LATEST).header.stamp == Time()  # no cache of its own


def test_v_tree_cross_branch(buf: Buffer) -> None:
    buf.set_transform(link("root", "left", 1.0, x=1.0), "me")
    buf.set_transform(link("root", "right", 1.0, x=-1.0, yaw=math.pi), "me")
    buf.set_transform(link("left", "l2", 1.0, y=1.0), "me")
    out = buf.lookup_transform("right", "l2", T(1.0))
    # l2 is at (1, 1) in root; right is at (-1, 0) facing -x: l2 is 2 behind, 1 to the right
    assert xyz(out) == pytest.approx((-2.0, -1.0, 0.0)) and abs(yaw(out)) == pytest.approx(math.pi)


def test_links_above_the_common_ancestor_do_not_matter(buf: Buffer) -> None:
    buf.set_transform(link("world", "x", 100.0), "me")  # no data near t = 1
    buf.set_transform(link("x", "lca", 1.0), "me")
    buf.set_transform(link("x", "lca", 2.0), "me")
    for t in (1.0, 2.0):
        buf.set_transform(link("lca", "a", t, x=t), "me")
        buf.set_transform(link("lca", "b", t, y=t), "me")
    assert xyz(buf.lookup_transform("a", "b", T(1.5))) == pytest.approx((-1.5, 1.5, 0.0))
    with pytest.raises(ExtrapolationException):
        buf.lookup_transform("world", "b", T(1.5))


def test_target_side_extrapolation_has_the_suffix(buf: Buffer) -> None:
    buf.set_transform(link("root", "a", 1.0), "me")
    buf.set_transform(link("root", "b", 5.0), "me")
    with pytest.raises(NoDataForExtrapolationException, match=r"from frame \[a\] to frame \[b\]"):
        buf.lookup_transform("b", "a", T(5.0))


# ---------------------------------------------------------------- A10/A12 names and errors


@pytest.mark.parametrize(
    ("target", "source", "exc", "text"),
    [
        ("", "b", InvalidArgumentException,
         ("Invalid argument passed to lookupTransform argument target_frame in tf2 frame_ids "
          "cannot be empty")),
        ("a", "/b", InvalidArgumentException,
         ("Invalid argument \"/b\" passed to lookupTransform argument source_frame - in tf2 "
          "frame_ids cannot start with a '/'")),
        ("a", "nope", LookupException,
         ('"nope" passed to lookupTransform argument source_frame does not exist. '
          "Known frames: a, b")),
    ],
)  # fmt: skip
def test_bad_names_in_lookup(
    buf: Buffer, target: str, source: str, exc: type[Exception], text: str
) -> None:
    buf.set_transform(link("a", "b", 1.0), "me")
    with pytest.raises(exc) as e:
        buf.lookup_transform(target, source, T(1.0))
    assert str(e.value) == text
    assert not buf.can_transform(target, source, T(1.0))


def test_can_transform_debug_strings(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0), "me")
    assert buf.can_transform("a", "b", T(1.0), return_debug_tuple=True) == (True, "")
    ok, why = buf.can_transform("x", "y", T(1.0), return_debug_tuple=True)
    assert not ok and why.splitlines()[0].startswith(
        'Invalid frame ID "x" passed to canTransform argument target_frame - frame does not exist'
    )
    assert 'Invalid frame ID "y" passed to canTransform argument source_frame' in why
    ok, why = buf.can_transform("a", "b", T(3.0), return_debug_tuple=True)
    assert not ok and "only time 1.000000000 is in the buffer" in why
    ok, why = buf.can_transform("/a", "b", T(1.0), return_debug_tuple=True)
    assert not ok and "cannot start with a '/'" in why


def test_exception_hierarchy() -> None:
    for cls in (BackwardExtrapolationException, ForwardExtrapolationException,
                NoDataForExtrapolationException):  # fmt: skip
        assert issubclass(cls, ExtrapolationException)
    for cls in (LookupException, ConnectivityException, ExtrapolationException,
                InvalidArgumentException):  # fmt: skip
        assert issubclass(cls, TransformException)


def test_time_arguments(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.5, x=1.0), "me")
    assert buf.lookup_transform("a", "b", 1_500_000_000).header.stamp == T(1.5)
    with pytest.raises(InvalidArgumentException, match="expected a Time or integer"):
        buf.lookup_transform("a", "b", 1.5)
    with pytest.raises(InvalidArgumentException, match="expected a duration >= 0"):
        Buffer(cache_time=-1.0)


# ---------------------------------------------------------------- A9 time travel


def test_time_travel_through_a_fixed_frame(buf: Buffer) -> None:
    for t, x in ((1.0, 1.0), (2.0, 2.0), (3.0, 3.0)):
        buf.set_transform(link("odom", "base", t, x=x), "me")
    out = buf.lookup_transform_full("base", T(3.0), "base", T(1.0), "odom")
    assert xyz(out) == pytest.approx((-2.0, 0.0, 0.0))
    assert out.header.stamp == T(3.0) and out.header.frame_id == "base"
    assert out.child_frame_id == "base"
    latest = buf.lookup_transform_full("base", LATEST, "base", T(2.0), "odom")
    assert latest.header.stamp == T(3.0) and xyz(latest)[0] == pytest.approx(-1.0)
    with pytest.raises(LookupException, match="fixed_frame does not exist"):
        buf.lookup_transform_full("base", T(3.0), "base", T(1.0), "map")
    with pytest.raises(ForwardExtrapolationException):
        buf.lookup_transform_full("base", T(3.0), "base", T(9.0), "odom")


def test_can_transform_full_legs(buf: Buffer) -> None:
    for t in (10.0, 20.0):
        buf.set_transform(link("parent", "child", t, x=t), "me")
    # the leg child <- child is always true, whatever its time
    assert buf.can_transform_full("child", T(5.0), "parent", T(15.0), "child")
    assert not buf.can_transform_full("child", T(5.0), "parent", T(15.0), "parent")
    ok, why = buf.can_transform_full("child", T(5.0), "parent", T(15.0), "parent",
                                     return_debug_tuple=True)  # fmt: skip
    assert not ok and "into the past" in why
    ok, why = buf.can_transform_full("child", T(5.0), "parent", T(15.0), "nope",
                                     return_debug_tuple=True)  # fmt: skip
    assert not ok and 'Invalid frame ID "nope"' in why and "fixed_frame" in why
    assert buf.can_transform_full("child", T(12.0), "parent", T(15.0), "parent",
                                  return_debug_tuple=True) == (True, "")  # fmt: skip


# ---------------------------------------------------------------- A11 loops


def test_loop_creating_insert_is_refused(buf: Buffer, caplog: pytest.LogCaptureFixture) -> None:
    assert buf.set_transform(link("a", "b", 1.0), "me")
    assert buf.set_transform(link("b", "c", 1.0), "me")
    with caplog.at_level(logging.WARNING, logger="zenros.tf"):
        assert not buf.set_transform(link("c", "a", 1.0), "me")
        assert not buf.set_transform_static(link("b", "a", 1.0), "me")
    assert "TF_LOOP" in caplog.text and "loop" in caplog.text
    with pytest.raises(InvalidArgumentException, match="TF_LOOP"):
        buf.set_transform(link("c", "a", 1.0), "me", strict=True)
    assert buf.get_parent("a", T(1.0)) is None
    assert buf.lookup_transform("a", "c", T(1.0)) is not None


def test_reparenting_that_is_not_a_loop_is_fine(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0), "me")
    buf.set_transform(link("root", "a", 1.0), "me")
    buf.set_transform(link("root", "b", 2.0, x=3.0), "me")  # b moves from a to root
    assert buf.get_parent("b", T(2.0)) == "root"


def test_deep_chain_has_no_depth_cap(buf: Buffer) -> None:
    n = 2500  # tf2 gives up after 1000
    for i in range(n):
        assert buf.set_transform(link(f"f{i}", f"f{i + 1}", 1.0, x=1.0), "me")
    assert xyz(buf.lookup_transform("f0", f"f{n}", T(1.0)))[0] == pytest.approx(n)
    assert xyz(buf.lookup_transform(f"f{n}", "f0", LATEST))[0] == pytest.approx(-n)
    assert buf.can_transform("f0", f"f{n}", T(1.0))


# ---------------------------------------------------------------- introspection


def test_frames_as_string_and_yaml(buf: Buffer) -> None:
    import yaml

    assert buf.all_frames_as_yaml() == "{}\n"
    buf.set_transform(link("map", "odom", 1.0), "loc")
    buf.set_transform(link("map", "odom", 3.0), "loc")
    buf.set_transform_static(link("odom", "base", 0.0), "urdf")
    assert buf.all_frames_as_string() == (
        "Frame odom exists with parent map.\nFrame base exists with parent odom.\n"
    )
    data = yaml.safe_load(buf.all_frames_as_yaml(T(4.0)))
    assert data["odom"] == {
        "parent": "map", "broadcaster": "loc", "rate": 1.0, "most_recent_transform": 3.0,
        "oldest_transform": 1.0, "transform_delay": 1.0, "buffer_length": 2.0,
    }  # fmt: skip
    assert data["base"]["parent"] == "odom" and data["base"]["broadcaster"] == "urdf"
    assert buf.get_parent("odom") == "map" and buf.get_parent("map") is None
    assert buf._frameExists("base")


def test_disjoint_trees_answer_false_without_walking(buf: Buffer) -> None:
    buf.set_transform(link("a", "b", 1.0), "me")
    buf.set_transform(link("c", "d", 1.0), "me")
    assert not buf.can_transform("b", "d", T(1.0))  # remembered as disjoint
    assert not buf.can_transform("b", "d", LATEST)
    buf.set_transform(link("a", "c", 1.0), "me")  # now joined: the memo is dropped
    assert buf.can_transform("b", "d", T(1.0))
