"""Unicycle integration and planar pose arithmetic."""

from __future__ import annotations

import math

import pytest
from zenros.se2 import Pose2, wrap_angle
from zenros.services.chassis.kinematics import integrate


def test_straight_and_arc() -> None:
    assert integrate(Pose2(1.0, 2.0, math.pi / 2), 0.5, 0.0, 2.0) == pytest.approx(
        (1.0, 3.0, math.pi / 2))
    # a quarter circle of radius 1 counter-clockwise from the origin facing +x
    p = integrate(Pose2(0.0, 0.0, 0.0), math.pi / 2, math.pi / 2, 1.0)
    assert p == pytest.approx((1.0, 1.0, math.pi / 2))
    # 50 small steps give the same as one big one (exact arcs)
    q = Pose2(0.0, 0.0, 0.0)
    for _ in range(50):
        q = integrate(q, math.pi / 2, math.pi / 2, 0.02)
    assert q == pytest.approx(p)


def test_compose_inverse_and_wrap() -> None:
    a = Pose2(1.0, 2.0, 0.7)
    b = Pose2(-0.5, 0.3, -2.0)
    assert a * a.inverse() == pytest.approx((0.0, 0.0, 0.0))
    assert a * b * b.inverse() == pytest.approx(a)
    assert wrap_angle(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
