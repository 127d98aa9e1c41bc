"""PathTracker: progress, distance remaining and the carrot along a polyline."""

from __future__ import annotations

import numpy as np
import pytest
from zenros.services.nav.motion.pathtrack import PathTracker


def test_progress_and_remaining_on_an_l_path() -> None:
    t = PathTracker(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]))
    assert t.length == pytest.approx(4.0)
    t.update(1.0, 0.1)
    assert t.position() == pytest.approx(1.0)
    assert t.distance_remaining(1.0, 0.1) == pytest.approx(3.1)
    assert t.carrot(1.0, 0.0, 0.5) == pytest.approx((1.5, 0.0))
    # a carrot round the corner is interpolated on the second leg, at the lookahead
    cx, cy = t.carrot(1.8, 0.0, 1.0)
    assert cx == pytest.approx(2.0) and np.hypot(cx - 1.8, cy) == pytest.approx(1.0)
    assert t.carrot(1.8, 0.0, 10.0) == (2.0, 2.0)  # nothing that far: the end
    assert t.carrot(1.0, 0.0, 1.5, max_s=1.8) == pytest.approx((1.8, 0.0))  # capped


def test_progress_never_jumps_to_a_later_part_that_passes_close() -> None:
    # a U: out along y = 0, back along y = 0.4; the robot on the way out stays there
    xy = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 0.4], [0.0, 0.4]])
    t = PathTracker(xy, search_dist=1.0)
    t.update(0.5, 0.25)  # nearer the way back, but that is beyond the search window
    assert t.index == 0 and t.position() == pytest.approx(0.5)


def test_single_point_path() -> None:
    t = PathTracker(np.array([[1.0, 1.0]]))
    assert t.update(0.0, 1.0) == pytest.approx(1.0)
    assert t.distance_remaining(0.0, 1.0) == pytest.approx(1.0)
    assert t.carrot(0.0, 0.0, 0.5) == (1.0, 1.0)
