"""qos: profiles, their liveliness tags, rclpy's int shorthand and invalid depths."""

from __future__ import annotations

from typing import Any

import pytest
from zenros.qos import (
    QOS_DEFAULT,
    QOS_LATCHED,
    QOS_SENSOR,
    Durability,
    QoSProfile,
    Reliability,
    as_profile,
)


def test_default_profile_is_reliable_volatile_depth_10() -> None:
    assert QoSProfile() == QOS_DEFAULT
    assert (QOS_DEFAULT.depth, QOS_DEFAULT.reliability, QOS_DEFAULT.durability) == (
        10, Reliability.RELIABLE, Durability.VOLATILE,
    )
    assert not QOS_DEFAULT.latched


def test_sensor_and_latched_presets() -> None:
    assert QOS_SENSOR.reliability is Reliability.BEST_EFFORT and not QOS_SENSOR.latched
    assert QOS_LATCHED.durability is Durability.TRANSIENT_LOCAL and QOS_LATCHED.latched
    assert QOS_LATCHED.depth == 1


@pytest.mark.parametrize(
    ("profile", "tag"),
    [
        (QoSProfile(), "rel+10"),
        (QoSProfile(depth=5, reliability=Reliability.BEST_EFFORT), "be+5"),
        (QoSProfile(depth=1, durability=Durability.TRANSIENT_LOCAL), "rel+tl+1"),
        (QoSProfile(depth=3, reliability=Reliability.BEST_EFFORT,
                    durability=Durability.TRANSIENT_LOCAL), "be+tl+3"),
        (QOS_SENSOR, "be+5"),
        (QOS_LATCHED, "rel+tl+1"),
    ],
)
def test_tags(profile: QoSProfile, tag: str) -> None:
    assert profile.tag == tag
    assert "/" not in tag and not any(c in tag for c in "*$?#")


def test_tags_are_distinct_for_distinct_profiles() -> None:
    profiles = {
        QoSProfile(depth=d, reliability=r, durability=u)
        for d in (1, 2, 10) for r in Reliability for u in Durability
    }
    assert len({p.tag for p in profiles}) == len(profiles)


def test_as_profile_passes_profiles_through() -> None:
    assert as_profile(QOS_SENSOR) is QOS_SENSOR


@pytest.mark.parametrize("depth", [1, 5, 1000])
def test_as_profile_int_shorthand(depth: int) -> None:
    assert as_profile(depth) == QoSProfile(depth=depth)


@pytest.mark.parametrize("bad", [True, False, 1.5, "5", None, [10]])
def test_as_profile_rejects_non_int_shorthand(bad: Any) -> None:
    with pytest.raises(TypeError, match="QoSProfile or an int depth"):
        as_profile(bad)


@pytest.mark.parametrize("depth", [0, -1])
def test_invalid_depth(depth: int) -> None:
    with pytest.raises(ValueError, match=f"depth must be >= 1, got {depth}"):
        QoSProfile(depth=depth)
    with pytest.raises(ValueError, match="depth must be >= 1"):
        as_profile(depth)


@pytest.mark.parametrize("depth", [2.5, True])
def test_non_integer_depth_is_rejected_by_the_profile(depth: Any) -> None:
    """Same rule as the shorthand: a depth is an int (it bounds a deque)."""
    with pytest.raises((TypeError, ValueError)):
        QoSProfile(depth=depth)


def test_profiles_are_frozen_and_hashable() -> None:
    with pytest.raises(AttributeError):
        QOS_DEFAULT.depth = 3  # type: ignore[misc, unused-ignore]
    assert {QoSProfile(): 1}[QoSProfile()] == 1


def test_enum_values_are_strings() -> None:
    assert Reliability("best_effort") is Reliability.BEST_EFFORT
    assert Durability("transient_local") is Durability.TRANSIENT_LOCAL
    assert Reliability.RELIABLE == "reliable"


@pytest.mark.parametrize("profile", [QOS_DEFAULT, QOS_SENSOR, QOS_LATCHED,
                                     QoSProfile(depth=7, reliability=Reliability.BEST_EFFORT,
                                                durability=Durability.TRANSIENT_LOCAL)])
def test_a_tag_gives_back_its_profile(profile: QoSProfile) -> None:
    assert QoSProfile.from_tag(profile.tag) == profile


@pytest.mark.parametrize(("tag", "expected"), [
    ("", QOS_DEFAULT), ("rel", QOS_DEFAULT),
    ("be+x", QoSProfile(reliability=Reliability.BEST_EFFORT)),
    ("rel+tl+0", QoSProfile(durability=Durability.TRANSIENT_LOCAL)),
    ("tl+3", QoSProfile(depth=3)),
])
def test_a_garbled_tag_falls_back_to_defaults(tag: str, expected: QoSProfile) -> None:
    assert QoSProfile.from_tag(tag) == expected
