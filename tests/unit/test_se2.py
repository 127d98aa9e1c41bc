"""se2: the planar pose the services share, its algebra and the angle wrap into [-pi, pi)."""

from __future__ import annotations

import math

import pytest
from zenros.se2 import Pose2, angle_diff, wrap_angle


@pytest.mark.parametrize(("angle", "wrapped"), [
    (0.0, 0.0), (math.pi, -math.pi), (-math.pi, -math.pi), (3 * math.pi / 2, -math.pi / 2),
    (-3 * math.pi / 2, math.pi / 2), (7.0, 7.0 - 2 * math.pi), (-20.0, -20.0 + 6 * math.pi),
])
def test_wrap_angle_is_into_minus_pi_to_pi(angle: float, wrapped: float) -> None:
    assert wrap_angle(angle) == pytest.approx(wrapped)
    assert -math.pi <= wrap_angle(angle) < math.pi


def test_angle_diff_is_the_shortest_turn() -> None:
    assert angle_diff(math.radians(170), math.radians(-170)) == pytest.approx(math.radians(-20))
    assert angle_diff(0.1, -0.1) == pytest.approx(0.2)


def test_compose_inverse_apply() -> None:
    a, b = Pose2(1.0, 2.0, 0.7), Pose2(-0.5, 0.3, -2.0)
    assert a * a.inverse() == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
    assert a.inverse() * a == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
    assert (a * b) * b.inverse() == pytest.approx(a)
    # b given in a's frame, expressed outside it: a applied to b's position
    ab = a * b
    assert ab[:2] == pytest.approx(a.apply(b.x, b.y))
    assert ab.theta == pytest.approx(wrap_angle(0.7 - 2.0))
    assert Pose2(0.0, 0.0, math.pi / 2).apply(1.0, 0.0) == pytest.approx((0.0, 1.0))
    assert Pose2(theta=3.0) * Pose2(theta=1.0) == pytest.approx((0.0, 0.0, 4.0 - 2 * math.pi))


def test_distance_finiteness_and_a_tuple_still() -> None:
    assert Pose2(1.0, 1.0).distance(Pose2(4.0, 5.0)) == 5.0
    assert Pose2() == (0.0, 0.0, 0.0) and Pose2(1.0, 2.0, 3.0).is_finite()
    assert not Pose2(math.nan, 0.0).is_finite()
    x, y, theta = Pose2(1.0, 2.0, 3.0)
    assert (x, y, theta) == (1.0, 2.0, 3.0)
    with pytest.raises(TypeError):
        Pose2() * 2  # noqa: B018 -- a Pose2 multiplies only a Pose2
