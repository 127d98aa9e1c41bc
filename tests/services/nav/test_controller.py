"""Regulated Pure Pursuit: the core formulas, and a unicycle following straight and curved
paths to the goal pose within the tolerances."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.se2 import Pose2, angle_diff
from zenros.services.nav.motion.controller import (
    ControllerParams,
    PurePursuit,
    cost_to_distance,
    curvature,
)

DT = 0.05


def drive(pp: PurePursuit, pose: Pose2, steps: int = 2000) -> tuple[Pose2, list[tuple[float, float, str]]]:
    """Integrate a unicycle under the controller until it says goal_reached."""
    log = []
    for _ in range(steps):
        out = pp.compute(pose, DT)
        log.append((out.v, out.w, out.state))
        if out.state == "goal_reached":
            break
        th = pose.theta + out.w * DT / 2
        pose = Pose2(pose.x + out.v * DT * math.cos(th), pose.y + out.v * DT * math.sin(th),
                     pose.theta + out.w * DT)
    return pose, log


def test_curvature_and_cost_distance_match_nav2() -> None:
    assert curvature(1.0, 0.0) == 0.0
    assert curvature(1.0, 1.0) == pytest.approx(1.0)
    assert curvature(0.01, 0.01) == 0.0  # carrot too close: no turn
    # the spec's worked example: c = 128, r_i = 0.22, csf = 3 -> 0.447 m, factor 0.745
    d = cost_to_distance(128, 0.22, 3.0)
    assert d == pytest.approx(0.447, abs=1e-3)
    assert 1.0 * d / 0.6 == pytest.approx(0.745, abs=1e-3)


def test_straight_path_reaches_goal_pose_within_tolerance() -> None:
    pp = PurePursuit()
    xy = np.column_stack([np.linspace(0, 5, 101), np.zeros(101)])
    pp.set_path(xy, goal_yaw=math.pi / 2)
    end, log = drive(pp, Pose2(0, 0.1, 0))
    assert log[-1][2] == "goal_reached"
    assert math.hypot(end.x - 5, end.y) <= pp.params.xy_goal_tolerance
    assert abs(angle_diff(math.pi / 2, end.theta)) <= pp.params.yaw_goal_tolerance
    assert max(v for v, _, _ in log) == pytest.approx(0.5)
    assert any(s == "rotating_to_goal" for _, _, s in log)


def test_curved_path_is_tracked_closely_and_slowed_in_the_tight_turn() -> None:
    pp = PurePursuit()
    a = np.linspace(-math.pi / 2, math.pi / 2, 200)  # a half circle of radius 0.6 m
    xy = np.column_stack([0.6 * np.cos(a), 0.6 + 0.6 * np.sin(a) - 0.6])
    xy = np.vstack([np.column_stack([np.linspace(-2, 0, 40), np.full(40, -0.6)]), xy[1:],
                    np.column_stack([np.linspace(0, -2, 40), np.full(40, 0.6)])[1:]])
    pp.set_path(xy, goal_yaw=None)
    pose = Pose2(-2, -0.6, 0)
    worst = 0.0
    speeds_in_turn = []
    for _ in range(3000):
        out = pp.compute(pose, DT)
        if out.state == "goal_reached":
            break
        d = float(np.min(np.hypot(xy[:, 0] - pose.x, xy[:, 1] - pose.y)))
        worst = max(worst, d)
        if pose.x > 0.3 and out.state == "following":
            speeds_in_turn.append(out.v)
        th = pose.theta + out.w * DT / 2
        pose = Pose2(pose.x + out.v * DT * math.cos(th), pose.y + out.v * DT * math.sin(th),
                     pose.theta + out.w * DT)
    else:
        pytest.fail("never reached the goal")
    assert math.hypot(pose.x + 2, pose.y - 0.6) <= pp.params.xy_goal_tolerance
    assert worst < 0.2
    assert speeds_in_turn and max(speeds_in_turn) < 0.45  # regulated below max in the turn


def test_rotates_in_place_toward_a_path_behind_the_robot() -> None:
    pp = PurePursuit()
    pp.set_path(np.array([[0.0, 0.0], [-3.0, 0.0]]), None)
    out = pp.compute(Pose2(0, 0, 0), DT)
    assert out.state == "rotating_to_path" and out.v == 0 and out.w != 0


def test_cost_near_obstacle_slows_the_robot() -> None:
    p = ControllerParams(max_linear_accel=100.0)
    fast, slow = PurePursuit(p), PurePursuit(p)
    xy = np.column_stack([np.linspace(0, 5, 101), np.zeros(101)])
    fast.set_path(xy, None)
    slow.set_path(xy, None)
    assert fast.compute(Pose2(), DT, cost_at_robot=0).v == pytest.approx(0.5)
    assert slow.compute(Pose2(), DT, cost_at_robot=200).v < 0.45


def test_acceleration_is_limited() -> None:
    pp = PurePursuit()
    pp.set_path(np.column_stack([np.linspace(0, 5, 101), np.zeros(101)]), None)
    out = pp.compute(Pose2(), 0.05)
    assert out.v == pytest.approx(pp.params.max_linear_accel * 0.05)  # 1.0 m/s^2, nav's default


def test_bad_parameters_and_paths_are_refused() -> None:
    with pytest.raises(ValueError, match="max_linear_vel"):
        PurePursuit(ControllerParams(max_linear_vel=0.0))
    with pytest.raises(ValueError, match="empty"):
        PurePursuit().set_path(np.zeros((0, 2)), None)
    with pytest.raises(ValueError, match="non-finite"):
        PurePursuit().set_path(np.array([[0.0, math.nan]]), None)
