"""Localizer: map->odom from ground truth and odometry, initial poses, mode switches."""

from __future__ import annotations

import math

import pytest
from zenros.se2 import Pose2
from zenros.services.nav.localization.localizer import Localizer

S = 1_000_000_000


def test_ground_truth_gives_map_to_odom_from_the_matching_odom_stamp() -> None:
    loc = Localizer()
    assert loc.pose() is None
    loc.on_odom(1 * S, Pose2(1.0, 0.0, 0.0))
    loc.on_odom(2 * S, Pose2(2.0, 0.0, 0.1))  # odometry drifted: the truth differs
    loc.on_ground_truth(1 * S, Pose2(5.0, 5.0, math.pi / 2))
    m2o = loc.map_to_odom
    assert m2o * Pose2(1.0, 0.0, 0.0) == pytest.approx(Pose2(5.0, 5.0, math.pi / 2))
    p = loc.pose()
    assert p is not None
    assert p == pytest.approx(m2o * Pose2(2.0, 0.0, 0.1))


def test_initial_pose_switches_to_odometry() -> None:
    loc = Localizer()
    loc.on_odom(1 * S, Pose2(1.0, 1.0, 0.5))
    loc.set_pose(Pose2(-2.0, 3.0, 1.0))
    assert loc.mode == "odometry" and loc.pose() == pytest.approx(Pose2(-2.0, 3.0, 1.0))
    loc.on_ground_truth(1 * S, Pose2(0.0, 0.0, 0.0))  # ignored now
    assert loc.pose() == pytest.approx(Pose2(-2.0, 3.0, 1.0))
    loc.on_odom(2 * S, Pose2(2.0, 1.0, 0.5))  # dead reckoning: 1 m along odom's x
    p = loc.pose()
    assert p is not None and math.hypot(p.x + 2.0, p.y - 3.0) == pytest.approx(1.0)
    loc.set_mode("ground_truth")
    loc.on_ground_truth(2 * S, Pose2(7.0, 7.0, 0.0))
    assert loc.pose() == pytest.approx(Pose2(7.0, 7.0, 0.0))
    with pytest.raises(ValueError, match="valid: ground_truth, odometry"):
        loc.set_mode("amcl")


def test_time_going_back_restarts_the_history() -> None:
    loc = Localizer()
    loc.on_odom(10 * S, Pose2(1.0, 0.0, 0.0))
    loc.on_odom(1 * S, Pose2(0.0, 0.0, 0.0))
    loc.on_ground_truth(1 * S, Pose2(0.0, 0.0, 0.0))
    assert loc.pose() == pytest.approx(Pose2())


def test_se2_algebra() -> None:
    a, b = Pose2(1.0, 2.0, 0.3), Pose2(-0.5, 0.7, -1.2)
    assert a * a.inverse() == pytest.approx(Pose2(0.0, 0.0, 0.0), abs=1e-12)
    assert (a * b).apply(0.0, 0.0) == pytest.approx(a.apply(b.x, b.y))
    assert Pose2(0, 0, math.pi) * Pose2(0, 0, math.pi) == pytest.approx(Pose2(0, 0, 0), abs=1e-9)


def test_the_same_truth_again_keeps_map_to_odom_and_still_overrides_a_fix() -> None:
    """At rest the same true pose and odometry come at every stamp: map->odom is the one
    they gave (not worked out again), unless something else set it meanwhile (a fix from
    a scan), which the next truth overrides as ever."""
    loc = Localizer()
    odom, truth = Pose2(1.0, 0.0, 0.2), Pose2(3.0, 4.0, 1.0)
    loc.on_odom(1 * S, odom)
    loc.on_ground_truth(1 * S, truth)
    m2o = loc.map_to_odom
    loc.on_odom(2 * S, odom)
    loc.on_ground_truth(2 * S, truth)
    assert loc.map_to_odom is m2o and loc.pose() == pytest.approx(truth)
    assert loc.set_pose_at(2 * S, Pose2(0.0, 0.0, 0.0))  # a fix; the mode stays
    assert loc.pose() == pytest.approx(Pose2(0.0, 0.0, 0.0))
    loc.on_odom(3 * S, odom)
    loc.on_ground_truth(3 * S, truth)
    assert loc.pose() == pytest.approx(truth)
