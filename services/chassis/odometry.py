"""Odometry: the pose in ``odom`` integrated from measured wheel velocities, with optional noise.

Without noise ``odom`` stays exactly where the robot started (map->odom is that start pose
until localisation corrects it); with noise the measured velocities carry a multiplicative
error, so the odometry drifts as a real one does. A teleport does not move ``odom`` (the
odometry never sees it, as in a kidnapped-robot test).
"""

from __future__ import annotations

import numpy as np
from zenros.se2 import Pose2

from .kinematics import integrate

__all__ = ["Odometry"]

# diff_drive_controller's defaults: x, y, z, roll, pitch, yaw
_POSE_COV = (0.001, 0.001, 1e6, 1e6, 1e6, 0.03)
_TWIST_COV = (0.001, 0.001, 1e6, 1e6, 1e6, 0.03)


class Odometry:
    """Integrates (v, w) into a pose in ``odom``; ``noise`` is the relative std dev of the
    measured speeds (0 = perfect odometry)."""

    def __init__(self, noise: float = 0.0, rng: np.random.Generator | None = None) -> None:
        if not noise >= 0:
            raise ValueError(f"odom_noise must be >= 0, got {noise}")
        self.noise = noise
        self.rng = rng or np.random.default_rng()
        self.pose = Pose2(0.0, 0.0, 0.0)
        self.linear = 0.0
        self.angular = 0.0

    def update(self, v: float, w: float, dt: float) -> Pose2:
        if self.noise > 0 and (v or w):
            ev, ew = self.rng.normal(0.0, self.noise, 2)
            v, w = v * (1 + ev), w * (1 + ew) + abs(v) * self.noise * 0.1 * ew
        self.linear, self.angular = v, w
        if v or w:  # standing still leaves the pose as it is (the same object)
            self.pose = integrate(self.pose, v, w, dt)
        return self.pose

    def pose_covariance(self) -> list[float]:
        return _diag(_POSE_COV, max(self.noise, 0.0))

    def twist_covariance(self) -> list[float]:
        return _diag(_TWIST_COV, max(self.noise, 0.0))


def _diag(base: tuple[float, ...], noise: float) -> list[float]:
    cov = [0.0] * 36
    for i, v in enumerate(base):
        cov[i * 7] = v if v >= 1e6 else v + noise * noise
    return cov
