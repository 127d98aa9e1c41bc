"""The IMU: ``imu`` (sensor_msgs/Imu) at ``imu_rate``, base_link -> ``imu_link`` on
``/tf_static``.

A planar robot's gyro and accelerometer: the yaw rate with the gyro's bias
(``imu_gyro_bias``) and noise, less the bias a calibration measured (none at power-up, as a
real IMU's driver starts), and the body's accelerations (tangential along x, centripetal
along y, gravity along z) with noise. No orientation (``orientation_covariance[0]`` is -1,
the REP 145 convention for an IMU that gives none).
"""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.clock import Time
from zenros.message import Float64Array, to_array
from zenros.msgs.geometry_msgs import Vector3
from zenros.msgs.sensor_msgs import Imu
from zenros.msgs.std_msgs import Header
from zenros.pubsub import Publisher
from zenros.qos import QOS_SENSOR
from zenros.se2 import Pose2

from .. import messages
from ..device import Chassis, Device, Endpoints
from ..param_types import NonNegative

__all__ = ["GRAVITY", "ImuDevice", "ImuParameters"]

GRAVITY = 9.80665  # m/s²


class ImuParameters(msgspec.Struct, kw_only=True, frozen=True):
    imu_rate: Annotated[NonNegative, Meta(
        description="IMU readings per sim second (0: no IMU)")] = 50.0
    imu_gyro_bias: Annotated[float, Meta(
        ge=-0.5, le=0.5, description="the gyro's yaw-rate bias (rad/s), which an IMU "
                                     "calibration measures")] = 0.004
    imu_gyro_noise: Annotated[NonNegative, Meta(
        description="std dev of the gyro's yaw rate (rad/s)")] = 0.002
    imu_accel_noise: Annotated[NonNegative, Meta(
        description="std dev of the accelerometer (m/s²)")] = 0.02
    imu_frame: str = "imu_link"


class ImuDevice(Device[ImuParameters]):
    """What the IMU measures: read every physics step (a calibration averages them), published
    at ``imu_rate`` while someone listens."""

    Parameters = ImuParameters
    _pub: Publisher[Imu]

    def __init__(self, params: ImuParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.rate = params.imu_rate
        self.inert = self.rate <= 0  # no IMU: nothing reads it (its calibration needs one)
        self.bias_estimate = 0.0  # what a calibration measured, taken off every reading
        self.gyro_raw = 0.0  # the last yaw rate as the sensor reads it (bias and noise in)
        self.accel = (0.0, 0.0)
        self._linear = 0.0

    @property
    def gyro(self) -> float:
        """The yaw rate as published: the raw reading less the calibrated bias."""
        return self.gyro_raw - self.bias_estimate

    def open(self, node: Endpoints) -> None:
        if self.rate <= 0:
            return
        self._pub = node.create_publisher(Imu, "imu", QOS_SENSOR)
        node.static_transform(messages.transform(
            node.stamp(), self.chassis.frames.base, self.params.imu_frame, Pose2(), 0.1))

    def step(self, dt: float) -> None:
        p, sim, rng = self.params, self.chassis.sim, self.chassis.rng
        noise = rng.normal(0.0, p.imu_gyro_noise) if p.imu_gyro_noise else 0.0
        self.gyro_raw = sim.angular + p.imu_gyro_bias + noise
        ax = (sim.linear - self._linear) / dt if dt > 0 else 0.0
        ay = sim.linear * sim.angular
        self._linear = sim.linear
        if p.imu_accel_noise:
            ax += rng.normal(0.0, p.imu_accel_noise)
            ay += rng.normal(0.0, p.imu_accel_noise)
        self.accel = (ax, ay)

    def publish(self, stamp: Time) -> None:
        if self.rate <= 0 or not self._pub.subscription_count:
            return
        p = self.params
        self._pub.publish(Imu(
            header=Header(stamp=stamp, frame_id=p.imu_frame),
            orientation_covariance=_diagonal(-1.0, 0.0),
            angular_velocity=Vector3(z=self.gyro),
            angular_velocity_covariance=_diagonal(p.imu_gyro_noise ** 2),
            linear_acceleration=Vector3(x=self.accel[0], y=self.accel[1], z=GRAVITY),
            linear_acceleration_covariance=_diagonal(p.imu_accel_noise ** 2)))


def _diagonal(first: float, rest: float | None = None) -> Float64Array:
    """A 3x3 covariance, row-major: ``first`` then ``rest`` (default ``first``) down the
    diagonal."""
    d = first if rest is None else rest
    out: Float64Array = to_array(Float64Array, [first, 0, 0, 0, d, 0, 0, 0, d])
    return out
