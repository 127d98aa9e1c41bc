"""Collision checks of a commanded arc against scan points."""

from __future__ import annotations

import numpy as np
import pytest
from zenros.services.nav.motion.collision import arc_poses, first_collision, points_in_frame


def test_straight_ahead_hits_at_the_right_time() -> None:
    wall = np.array([[1.0, y] for y in np.linspace(-1, 1, 41)])
    t = first_collision(0.5, 0.0, wall, radius=0.2, horizon=3.0, step=0.01)
    assert t == pytest.approx((1.0 - 0.2) / 0.5, abs=0.03)
    assert first_collision(0.5, 0.0, wall, radius=0.2, horizon=1.0) is None  # too far yet
    assert first_collision(-0.5, 0.0, wall, radius=0.2, horizon=3.0) is None  # backing away
    assert first_collision(0.0, 1.0, wall, radius=0.2, horizon=3.0) is None  # turning in place


def test_arc_misses_what_a_straight_line_would_hit() -> None:
    post = np.array([[1.0, 0.0]])
    assert first_collision(0.5, 0.0, post, 0.2, 3.0) is not None
    assert first_collision(0.5, 1.0, post, 0.2, 3.0) is None  # turns left, round it
    arc = arc_poses(0.5, 1.0, np.pi)
    assert arc[-1, 1:3] == pytest.approx([0.0, 1.0], abs=1e-9)  # a half circle of r 0.5


def test_points_in_frame() -> None:
    pts = points_in_frame(np.array([[1.0, 1.0]]), 1.0, 0.0, np.pi / 2)
    assert pts[0] == pytest.approx([1.0, 0.0])
    assert points_in_frame(np.zeros((0, 2)), 0, 0, 0).shape == (0, 2)
