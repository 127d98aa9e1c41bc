"""ScanMatcher: a scan ray-cast on the demo map from a known pose is matched back to that
pose from a guess 15 cm and 3 degrees off; a scan that fits nowhere scores low."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.maps import GridMap, load_map
from zenros.se2 import Pose2
from zenros.services.nav.localization.localizer import Localizer
from zenros.services.nav.localization.scanmatch import ScanMatcher
from zenros.services.nav.params import DEMO_MAP


def cast(grid: GridMap, pose: Pose2, n: int = 360, rmax: float = 8.0) -> np.ndarray:
    """End points (robot frame) of ``n`` beams marched through the grid in 1 cm steps."""
    a = np.linspace(-math.pi, math.pi, n, endpoint=False)
    r = np.arange(0.05, rmax, 0.01)
    x = pose.x + np.cos(a + pose.theta)[:, None] * r[None, :]
    y = pose.y + np.sin(a + pose.theta)[:, None] * r[None, :]
    mx = np.floor((x - grid.origin[0]) / grid.resolution).astype(int)
    my = np.floor((y - grid.origin[1]) / grid.resolution).astype(int)
    ok = (mx >= 0) & (mx < grid.width) & (my >= 0) & (my < grid.height)
    hit = np.zeros_like(ok)
    hit[ok] = grid.grid[my[ok], mx[ok]] >= 65
    found = hit.any(axis=1)
    rng = r[hit.argmax(axis=1)][found]
    return np.column_stack([rng * np.cos(a[found]), rng * np.sin(a[found])])


@pytest.fixture(scope="module")
def office() -> tuple[GridMap, ScanMatcher]:
    grid = load_map(DEMO_MAP)
    return grid, ScanMatcher(grid)


@pytest.mark.parametrize("truth", [Pose2(0.0, 0.0, 0.0), Pose2(10.0, 0.3, 0.5),
                                   Pose2(22.0, -5.0, 1.0), Pose2(5.0, 4.0, -2.0)])
def test_match_recovers_the_pose(office: tuple[GridMap, ScanMatcher], truth: Pose2) -> None:
    grid, sm = office
    pts = cast(grid, truth)
    guess = Pose2(truth.x + 0.12, truth.y - 0.09, truth.theta + 0.05)
    found, score = sm.match(pts, guess)
    assert found.distance(truth) < 0.02
    assert abs(math.remainder(found.theta - truth.theta, 2 * math.pi)) < 0.01
    assert score > 0.8 and score > sm.score(pts, guess) + 0.2


def test_a_scan_that_fits_nowhere_scores_low(office: tuple[GridMap, ScanMatcher]) -> None:
    _, sm = office
    a = np.linspace(0, 2 * math.pi, 100, endpoint=False)
    ring = np.column_stack([0.7 * np.cos(a), 0.7 * np.sin(a)])  # a circle the map lacks
    _, score = sm.match(ring, Pose2(10.0, 0.0, 0.0))
    assert score < sm.p.min_score
    assert sm.match(ring[:5], Pose2(1.0, 1.0, 0.0)) == (Pose2(1.0, 1.0, 0.0), 0.0)


def test_correction_moves_map_to_odom_by_the_gain() -> None:
    loc = Localizer("scan_match")
    assert loc.localized
    loc.on_odom(1, Pose2(1.0, 0.0, 0.0))
    loc.correct(1, Pose2(1.2, 0.0, 0.0), gain=0.5)  # the matcher says 20 cm further
    assert loc.pose() == pytest.approx(Pose2(1.1, 0.0, 0.0))
    assert loc.corrections == 1


@pytest.mark.parametrize("truth", [Pose2(10.0, 0.3, 0.5), Pose2(5.0, 4.0, -2.0)])
def test_the_wide_window_finds_a_pose_given_off_by_more_than_tracking_s(
        office: tuple[GridMap, ScanMatcher], truth: Pose2) -> None:
    """A relocalisation (initial pose, a built map's saved map -> odom): 0.35 m and 0.25 rad
    off is outside the tracking window, inside the wide one."""
    grid, sm = office
    pts = cast(grid, truth)
    guess = Pose2(truth.x - 0.25, truth.y + 0.25, truth.theta - 0.25)
    narrow, _ = sm.match(pts, guess)
    assert narrow.distance(truth) > 0.1
    wide, score = sm.match(pts, guess, wide=True)
    found, score = sm.match(pts, wide)
    assert found.distance(truth) < 0.02 and score > 0.8


def test_external_map_to_odom_is_taken_as_it_is() -> None:
    """Mapping mode: the SLAM node's transform only; truth, matches, initial poses ignored."""
    loc = Localizer("ground_truth")
    loc.on_odom(1, Pose2(1.0, 0.0, 0.0))
    loc.set_external(True)
    assert loc.pose() is None
    loc.on_ground_truth(1, Pose2(5.0, 5.0, 0.0))
    loc.set_pose(Pose2(7.0, 7.0, 0.0))
    assert loc.pose() is None
    loc.follow(Pose2(0.5, 0.0, 0.0))
    assert loc.pose() == Pose2(1.5, 0.0, 0.0)
    loc.set_mode("scan_match")
    loc.correct(1, Pose2(9.0, 9.0, 0.0), 1.0)
    assert loc.pose() == Pose2(1.5, 0.0, 0.0)
    loc.set_external(False)
    loc.follow(Pose2(3.0, 0.0, 0.0))  # no longer followed
    assert loc.map_to_odom == Pose2(0.5, 0.0, 0.0)
    loc.set_pose(Pose2(2.0, 0.0, 0.0))
    assert loc.relocalize and loc.pose() == Pose2(2.0, 0.0, 0.0)
    loc.correct(1, Pose2(2.1, 0.0, 0.0), 1.0)
    assert not loc.relocalize
