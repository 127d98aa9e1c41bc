"""Static transforms from the ``static_transforms`` parameter."""

from __future__ import annotations

import math
from typing import Any

import pytest
from zenros.errors import InvalidParameterValueError
from zenros.msgs.builtin_interfaces import Time
from zenros.services.tf.static import parse_static_transforms
from zenros.tf import euler_from_quaternion, quaternion_from_msg, transform_from_msg


def test_string_forms_as_static_transform_publisher_takes_them() -> None:
    a, b = parse_static_transforms([
        "0.1 0 0.2 1.5707963 0 0 base_link laser",
        "1 2 3 0 0 0 2 /map odom",  # a quaternion, normalised
    ], Time(sec=7))  # fmt: skip
    assert a.header.frame_id == "base_link" and a.child_frame_id == "laser"
    assert a.header.stamp == Time(sec=7)
    x, y, z, *q = transform_from_msg(a)
    assert (x, y, z) == (0.1, 0.0, 0.2)
    roll, _pitch, yaw = euler_from_quaternion(tuple(q))  # type: ignore[arg-type]
    assert yaw == pytest.approx(math.pi / 2) and roll == pytest.approx(0.0)
    assert quaternion_from_msg(b.transform.rotation) == (0.0, 0.0, 0.0, 1.0)
    assert b.header.frame_id == "/map"  # the buffer strips the '/' when it stores it


def test_yaw_pitch_roll_order() -> None:
    (t,) = parse_static_transforms(["0 0 0 0.1 0.2 0.3 a b"])
    roll, pitch, yaw = euler_from_quaternion(quaternion_from_msg(t.transform.rotation))
    assert (yaw, pitch, roll) == pytest.approx((0.1, 0.2, 0.3))


def test_mapping_forms() -> None:
    a, b = parse_static_transforms([
        {"parent": "base_link", "child": "laser", "x": 0.1, "z": 0.2, "yaw": 0.5},
        {"frame_id": "base_link", "child_frame_id": "imu", "qz": 1.0, "qw": 0},
    ])  # fmt: skip
    assert a.transform.translation.x == 0.1 and a.transform.translation.z == 0.2
    assert euler_from_quaternion(quaternion_from_msg(a.transform.rotation))[2] == (
        pytest.approx(0.5))
    assert b.child_frame_id == "imu"
    assert quaternion_from_msg(b.transform.rotation) == (0.0, 0.0, 1.0, 0.0)
    (c,) = parse_static_transforms([{"parent": "a", "child": "b"}])
    assert quaternion_from_msg(c.transform.rotation) == (0.0, 0.0, 0.0, 1.0)


def test_empty_list_gives_no_links() -> None:
    assert parse_static_transforms([]) == []


@pytest.mark.parametrize(("items", "match"), [
    ("0 0 0 0 0 0 a b", "expected a list"),
    (["0 0 0 a b"], r"\[0\].*expected 'x y z yaw pitch roll parent child'"),
    (["0 0 zero 0 0 0 a b"], r"expected a number, got 'zero'"),
    (["0 0 0 0 0 0 a /a"], r"\[0\].*its own parent"),
    (["0 0 0 0 0 0 / b"], "must not be empty"),
    ([42], r"\[0\].*expected a string"),
    ([{"parent": "a"}], r"expected one non-empty string for child or child_frame_id"),
    ([{"parent": "a", "child": "b", "yaw": 1, "qw": 1}], "not both"),
    ([{"parent": "a", "child": "b", "height": 1}], "unknown key.*height.*valid"),
    ([{"parent": "a", "child": "b", "x": "1"}], "x must be a number"),
    ([{"parent": "a", "child": "b", "x": float("nan")}], "finite"),
    (["0 0 0 0 0 0 0 a b"], "no length"),
    (["0 0 0 0 0 0 a b", "1 0 0 0 0 0 c b"], "b given more than once"),
])  # fmt: skip
def test_bad_items_name_the_item_and_the_problem(items: Any, match: str) -> None:
    with pytest.raises(InvalidParameterValueError, match=match):
        parse_static_transforms(items)
