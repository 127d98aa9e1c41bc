"""The mapper: the map frame is the first scan's odometry pose, scans are gated by travel, a
drive along a room keeps the pose, and a stored grid can be extended."""

from __future__ import annotations

import math

import numpy as np
from slam_worlds import ROOM, cast
from zenros.se2 import Pose2
from zenros.services.slam.mapper import Mapper, Prior
from zenros.services.slam.params import SlamParameters


def _room_grid(res: float = 0.05) -> Prior:
    cells = np.zeros((int(6.4 / res), int(10.4 / res)), np.int8)  # origin (-0.2, -0.2)
    for x0, y0, x1, y1 in ROOM:
        n = int(math.hypot(x1 - x0, y1 - y0) / 0.005) + 1
        xs, ys = np.linspace(x0, x1, n), np.linspace(y0, y1, n)
        cells[((ys + 0.2) / res).astype(int).clip(0, cells.shape[0] - 1),
              ((xs + 0.2) / res).astype(int).clip(0, cells.shape[1] - 1)] = 100
    return Prior(cells, res, (-0.2, -0.2))


def test_the_map_frame_is_the_first_scans_odometry_and_gating_holds() -> None:
    m = Mapper()
    odom0 = Pose2(0.3, -0.2, 0.1)
    start = Pose2(2.0, 1.5, 0.1)  # where the robot is in the room (unknown to the mapper)
    out = m.add_scan(0.0, odom0, cast(ROOM, start))
    assert out.node == 0 and np.allclose(out.pose, odom0) and np.allclose(m.map_to_odom, 0)
    small = odom0 * Pose2(0.2, 0.0, 0.1)
    assert m.add_scan(0.1, small, cast(ROOM, start * Pose2(0.2, 0.0, 0.1))).node is None
    assert m.nodes == 1 and np.allclose(m.pose, small)


def test_a_drive_along_the_room_keeps_the_pose_with_drifting_odometry() -> None:
    # a robot whose odometry is poorer than the defaults assume, and says so
    m = Mapper(SlamParameters(odom_translation_sigma=0.1, odom_drift_sigma=0.05))
    rng = np.random.default_rng(4)
    truth, odom = Pose2(1.5, 1.0, 0.0), Pose2()
    start = truth
    for k in range(60):
        step = Pose2(0.1, 0.0, 0.0) if k < 50 else Pose2(0.0, 0.0, 0.15)
        truth = truth * step
        odom = odom * Pose2(step.x * 1.05, rng.normal(0, 0.003), step.theta + 0.004)  # drifts
        out = m.add_scan(0.1 * k, odom, cast(ROOM, truth, noise=0.01, seed=k))
    want = start.inverse() * truth
    assert math.hypot(out.pose.x - want.x, out.pose.y - want.y) < 0.1
    assert abs(out.pose.theta - want.theta) < 0.03
    drift = start.inverse() * truth
    assert math.hypot(odom.x - drift.x, odom.y - drift.y) > 0.2  # the odometry alone was off


def test_extending_a_stored_grid_relocalises_on_its_walls() -> None:
    m = Mapper()
    prior = _room_grid()
    truth = Pose2(5.5, 1.2, 0.3)
    m.resume_on_grid(prior, Pose2(5.7, 1.05, 0.34))  # told a pose 0.25 m and 2 degrees off
    out = m.add_scan(0.0, Pose2(), cast(ROOM, truth, noise=0.01))
    assert out.node == 0
    assert math.hypot(out.pose.x - truth.x, out.pose.y - truth.y) < 0.06
    assert abs(out.pose.theta - truth.theta) < 0.02
    occ = m.grid.occupancy()
    assert (occ == 100).sum() >= (prior.cells == 100).sum() * 0.9  # the stored walls stay
