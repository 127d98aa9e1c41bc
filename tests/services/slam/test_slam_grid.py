"""The log-odds grid marks returns, clears the beams before them, and never marks a beam that
had no return."""

from __future__ import annotations

import math

import numpy as np
from slam_worlds import ROOM, cast
from zenros.se2 import Pose2
from zenros.services.slam.grid import LogOddsGrid
from zenros.services.slam.scan import RangeScan


def _cell(g: LogOddsGrid, x: float, y: float) -> tuple[int, int]:
    return math.floor((y - g.oy) / g.res), math.floor((x - g.ox) / g.res)


def test_walls_marked_free_space_cleared() -> None:
    g = LogOddsGrid(0.05)
    for k in range(5):
        g.add_scan(Pose2(5.0, 1.0, 0.1 * k), cast(ROOM, Pose2(5.0, 1.0, 0.1 * k)))
    occ = g.occupancy()
    assert occ[_cell(g, 5.0, -0.02)] == 100  # the wall at y = 0, just below
    assert occ[_cell(g, 5.0, 0.5)] == 0  # between the robot and that wall
    assert occ[_cell(g, 5.0, 1.0)] == 0
    assert occ[_cell(g, 3.5, 2.5)] == -1  # inside the pillar: never seen
    assert g.known_area() > 20.0


def test_no_return_clears_and_never_marks() -> None:
    g = LogOddsGrid(0.05)
    ranges = np.full(8, np.inf, dtype=np.float32)
    scan = RangeScan.from_laser(ranges, 0.0, math.pi / 4, Pose2(), 0.05, 12.0, 20.0, 3.0)
    for _ in range(5):
        g.add_scan(Pose2(), scan)
    occ = g.occupancy()
    assert not (occ == 100).any()
    assert occ[_cell(g, 2.0, 0.0)] == 0  # along the first beam, within the clear range
    assert occ[_cell(g, 4.0, 0.0)] == -1  # past it


def test_a_cell_flips_back_when_seen_free() -> None:
    g = LogOddsGrid(0.05)
    wall = RangeScan.from_laser(np.array([2.0], np.float32), 0.0, 0.1, Pose2(), 0.05, 12.0,
                                20.0, 6.0)
    far = RangeScan.from_laser(np.array([4.0], np.float32), 0.0, 0.1, Pose2(), 0.05, 12.0,
                               20.0, 6.0)
    for _ in range(6):
        g.add_scan(Pose2(), wall)
    assert g.occupancy()[_cell(g, 2.01, 0.0)] == 100
    for _ in range(16):  # the thing at 2 m moved away
        g.add_scan(Pose2(), far)
    assert g.occupancy()[_cell(g, 2.01, 0.0)] == 0


def test_grows_to_hold_what_is_cast() -> None:
    g = LogOddsGrid(0.05)
    g.add_scan(Pose2(), cast(ROOM, Pose2(1.0, 1.0, 0.0)))
    h, w = g.shape
    g.add_scan(Pose2(40.0, -30.0, 0.0), cast(ROOM, Pose2(1.0, 1.0, 0.0)))
    assert g.shape[0] > h and g.shape[1] > w
    assert g.ox < -1.0 and g.oy < -31.0
