"""The correlative matcher recovers a known offset, coarse to fine, and says how sure it is."""

from __future__ import annotations

import math

import numpy as np
import pytest
from slam_worlds import ROOM, cast
from zenros.se2 import Pose2
from zenros.services.slam.mapper import Mapper
from zenros.services.slam.matcher import CorrelationGrid, Window, match
from zenros.services.slam.scan import points_in

TRUTH = Pose2(5.5, 1.2, 0.3)


def _setup(noise: float = 0.0) -> tuple[CorrelationGrid, np.ndarray]:
    ref = np.vstack([points_in(p, cast(ROOM, p, noise=noise, seed=k).points)
                     for k, p in enumerate([Pose2(5.0, 1.0, 0.0), Pose2(6.0, 1.5, 0.5)])])
    grid = CorrelationGrid(ref, 0.05, 0.05, 1.0)
    return grid, cast(ROOM, TRUTH, noise=noise, seed=9).points


@pytest.mark.parametrize("offset", [(0.12, -0.08, 0.05), (-0.15, 0.1, -0.08), (0.0, 0.0, 0.0)])
def test_recovers_a_known_offset(offset: tuple[float, float, float]) -> None:
    grid, pts = _setup()
    guess = Pose2(TRUTH.x + offset[0], TRUTH.y + offset[1], TRUTH.theta + offset[2])
    res = match(grid, pts[::2], guess, Mapper().window, pts)
    assert math.hypot(res.pose.x - TRUTH.x, res.pose.y - TRUTH.y) < 0.03  # under a cell
    assert abs(res.pose.theta - TRUTH.theta) < math.radians(0.3)
    assert res.response > 0.8
    assert res.covariance[0, 0] < 0.01 and res.covariance[1, 1] < 0.01


def test_noisy_ranges_still_match_within_a_centimetre() -> None:
    grid, pts = _setup(noise=0.02)
    guess = Pose2(TRUTH.x - 0.1, TRUTH.y + 0.1, TRUTH.theta + 0.04)
    res = match(grid, pts[::2], guess, Mapper().window, pts)
    assert math.hypot(res.pose.x - TRUTH.x, res.pose.y - TRUTH.y) < 0.03
    assert abs(res.pose.theta - TRUTH.theta) < math.radians(0.5)


def test_a_wide_window_on_a_pooled_grid_finds_a_far_offset() -> None:
    grid, pts = _setup()
    win = Window(xy=1.5, xy_step=0.2, theta=0.3, theta_step=0.0349, fine_xy=0.025,
                 fine_theta=0.0035, pool=4, candidates=4)
    guess = Pose2(TRUTH.x + 0.9, TRUTH.y - 0.7, TRUTH.theta - 0.15)
    res = match(grid, pts[::2], guess, win, pts)
    assert math.hypot(res.pose.x - TRUTH.x, res.pose.y - TRUTH.y) < 0.03
    assert abs(res.pose.theta - TRUTH.theta) < math.radians(0.5)


def test_pooled_grid_bounds_the_fine_one() -> None:
    grid, _ = _setup()
    pooled = grid.pooled(4)
    f, p = grid.field, pooled.field
    for r, c in [(40, 40), (60, 100), (20, 150)]:
        assert p[r, c] >= f[r:r + 4, c:c + 4].max() - 1e-6


def test_no_points_is_no_match() -> None:
    grid, _ = _setup()
    res = match(grid, np.zeros((0, 2)), TRUTH, Mapper().window)
    assert res.response == 0.0 and res.pose == TRUTH
