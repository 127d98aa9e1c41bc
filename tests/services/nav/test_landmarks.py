"""Landmark relocalisation without a network: the reflector detector, the matcher and the
rigid fit, on scans the simulated laser casts in the demo office."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from zenros.maps import load_landmarks, load_map
from zenros.se2 import Pose2, angle_diff
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.reflectors import STRONG, Reflectors
from zenros.services.chassis.world import World
from zenros.services.nav.localization.landmarks import (
    LandmarkError,
    LocateParams,
    fit_rigid,
    locate,
)
from zenros.services.nav.localization.reflectors import DetectParams, detect

OFFICE = Path(__file__).parents[3] / "deploy" / "maps" / "office" / "office.yaml"
MOUNT = Pose2(0.1, 0.0, 0.0)


@pytest.fixture(scope="module")
def office() -> tuple[Laser, Reflectors, np.ndarray]:
    cfg = LaserConfig(noise=0.01)
    marks = load_landmarks(OFFICE)
    laser = Laser(World(load_map(OFFICE)), cfg, np.random.default_rng(7))
    return laser, Reflectors(marks), np.array([(m.x, m.y) for m in marks])


def scan(office: tuple[Laser, Reflectors, np.ndarray], truth: Pose2
         ) -> tuple[np.ndarray, np.ndarray]:
    laser, refl, _ = office
    cfg = laser.config
    p = truth * MOUNT
    angles = cfg.angle_min + np.arange(cfg.beams) * cfg.angle_increment
    ranges = laser.ranges(p.x, p.y, p.theta)
    return ranges, refl.intensities(p.x, p.y, p.theta, angles, ranges, cfg.range_max)


def observe(office: tuple[Laser, Reflectors, np.ndarray], truth: Pose2) -> np.ndarray:
    ranges, intensities = scan(office, truth)
    cfg = office[0].config
    return detect(ranges, intensities, cfg.angle_min, cfg.angle_increment, cfg.range_min,
                  cfg.range_max, MOUNT).xy


def test_fit_rigid_recovers_a_motion_exactly() -> None:
    rng = np.random.default_rng(1)
    src = rng.uniform(-5, 5, (6, 2))
    want = Pose2(1.5, -2.0, 0.7)
    dst = np.array([want.apply(x, y) for x, y in src])
    got = fit_rigid(src, dst)
    assert got.distance(want) < 1e-9 and abs(angle_diff(got.theta, want.theta)) < 1e-9
    with pytest.raises(LandmarkError, match="two or more point pairs"):
        fit_rigid(src[:1], dst[:1])
    with pytest.raises(LandmarkError, match="coincide"):
        fit_rigid(np.zeros((2, 2)), dst[:2])


def test_detector_finds_each_reflector_in_reach(office: tuple[Laser, Reflectors, np.ndarray]
                                                 ) -> None:
    """From the corridor's west end, each detection is within 5 cm of a reflector."""
    truth = Pose2(0.0, 0.0, 0.3)
    found = observe(office, truth)
    assert len(found) >= 4
    in_map = np.array([truth.apply(x, y) for x, y in found])
    nearest = np.min(np.hypot(*(in_map[:, None] - office[2][None]).transpose(2, 0, 1)), axis=1)
    assert np.all(nearest < 0.05), nearest


def test_detector_edge_cases() -> None:
    n = 360
    inc = 2 * math.pi / n
    ranges = np.full(n, 2.0)
    assert len(detect(ranges, np.zeros(0), -math.pi, inc, 0.05, 12.0)) == 0  # no intensities
    with pytest.raises(ValueError, match="360 ranges but 3 intensities"):
        detect(ranges, np.zeros(3), -math.pi, inc, 0.05, 12.0)
    with pytest.raises(ValueError, match="not finite"):
        detect(ranges, np.zeros(n), math.nan, inc, 0.05, 12.0)
    # a strong run across the scan's seam (beams 359 and 0) is one reflector
    intensities = np.zeros(n)
    intensities[[0, n - 1]] = STRONG
    found = detect(ranges, intensities, -math.pi, inc, 0.05, 12.0)
    assert len(found) == 1 and found.returns.tolist() == [2]
    a = -math.pi + (n - 1) * inc
    assert found.xy[0] == pytest.approx([(-2.0 + 2.0 * math.cos(a)) / 2, math.sin(a)], abs=1e-9)
    # a strong stretch wider than a reflector (a mirror) is dropped
    intensities[:] = 0
    intensities[100:120] = STRONG
    assert len(detect(ranges, intensities, -math.pi, inc, 0.05, 12.0, None,
                      DetectParams(max_width=0.3))) == 0


@pytest.mark.parametrize("rough", [True, False])
def test_relocalises_across_the_office(office: tuple[Laser, Reflectors, np.ndarray],
                                       rough: bool) -> None:
    """Poses along the corridor, any heading, the estimate 1 m and 20 degrees off: every
    fix within 5 cm and 1 degree of the truth. With no estimate at all a few poses are
    refused as ambiguous (the office's layout is nearly symmetric there), never wrong."""
    rng = np.random.default_rng(3)
    refused = 0
    for _ in range(40):
        truth = Pose2(rng.uniform(-2, 25), rng.uniform(-0.8, 0.8), rng.uniform(-3.1, 3.1))
        guess = Pose2(truth.x + 0.8, truth.y - 0.6, truth.theta + math.radians(20))
        try:
            fix = locate(observe(office, truth), office[2], guess if rough else None)
        except LandmarkError as exc:
            assert not rough and "equally well" in str(exc)
            refused += 1
            continue
        assert truth.distance(fix.pose) < 0.05, (truth, fix)
        assert abs(angle_diff(fix.pose.theta, truth.theta)) < math.radians(1.0)
        assert len(fix.matches) >= 2 and fix.rms < 0.05
    assert refused <= 4


def test_a_spurious_strong_return_is_left_out(office: tuple[Laser, Reflectors, np.ndarray]
                                              ) -> None:
    """A shiny thing 1.3 m ahead is detected but matches no landmark; the fix ignores it."""
    truth = Pose2(6.0, 0.2, -0.4)
    obs = observe(office, truth)
    with_ghost = np.vstack([obs, [[1.3, 0.1]]])
    fix = locate(with_ghost, office[2], truth)
    assert len(with_ghost) - 1 not in {i for i, _ in fix.matches}
    assert truth.distance(fix.pose) < 0.05


def test_refusals_are_clear(office: tuple[Laser, Reflectors, np.ndarray]) -> None:
    marks = office[2]
    with pytest.raises(LandmarkError, match="the scan shows 1 reflector"):
        locate(np.array([[1.0, 0.0]]), marks, Pose2())
    with pytest.raises(LandmarkError, match="the map has 1 landmark"):
        locate(np.array([[1.0, 0.0], [0.0, 1.0]]), marks[:1], Pose2())
    with pytest.raises(LandmarkError, match="needs at least 3"):
        locate(np.array([[1.0, 0.0], [0.0, 1.0]]), marks, Pose2(),
               LocateParams(min_matches=3))
    # two "reflectors" 40 m apart: no pair of landmarks is that far apart
    with pytest.raises(LandmarkError, match="no pose matches 2"):
        locate(np.array([[20.0, 0.0], [-20.0, 0.0]]), marks, Pose2())


def test_a_symmetric_layout_needs_a_rough_pose() -> None:
    """Four landmarks on a square: two seen, several poses fit; the rough pose chooses."""
    marks = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
    truth = Pose2(2.0, 1.0, 0.0)
    inv = truth.inverse()
    obs = np.array([inv.apply(*marks[0]), inv.apply(*marks[1])])
    with pytest.raises(LandmarkError, match="poses fit the 2 reflectors seen equally well"):
        locate(obs, marks)
    fix = locate(obs, marks, Pose2(2.3, 1.4, 0.2))
    assert fix.pose.distance(truth) < 1e-6
