"""The wheel odometry: ``odom`` (nav_msgs/Odometry) and odom -> base_link on ``/tf``."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.nav_msgs import Odometry as OdometryMsg
from zenros.pubsub import Publisher
from zenros.se2 import Pose2
from zenros.tf import TransformBroadcaster

from .. import messages
from ..device import Chassis, Device, Endpoints
from ..odometry import Odometry
from ..param_types import NonNegative

__all__ = ["OdometryDevice", "OdometryParameters"]


class OdometryParameters(msgspec.Struct, kw_only=True, frozen=True):
    odom_noise: Annotated[NonNegative, Meta(
        description="relative std dev of the odometry's speeds")] = 0.0
    publish_tf: Annotated[bool, Meta(description="publish odom -> base_link on /tf")] = True


class OdometryDevice(Device[OdometryParameters]):
    """What the wheels measure (`Odometry`: the pose in ``odom``, drifting with noise),
    published every physics step."""

    Parameters = OdometryParameters
    _pub: Publisher[OdometryMsg]
    _tf: TransformBroadcaster | None

    def __init__(self, params: OdometryParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.odometry = Odometry(params.odom_noise, chassis.rng)
        self.rate = chassis.step_rate
        frames = chassis.frames
        self._stream = messages.OdometryStream(
            frames.odom, frames.base, messages.covariance(self.odometry.pose_covariance()),
            messages.covariance(self.odometry.twist_covariance()))

    @property
    def odom_in_map(self) -> Pose2:
        """The ``odom`` frame's pose in ``map`` as the simulator knows it (truth ∘ odom⁻¹)."""
        return self.chassis.sim.truth * self.odometry.pose.inverse()

    def open(self, node: Endpoints) -> None:
        self._pub = node.create_publisher(OdometryMsg, "odom")
        self._tf = node.transforms() if self.params.publish_tf else None

    def step(self, dt: float) -> None:
        sim = self.chassis.sim
        self.odometry.update(sim.linear, sim.angular, dt)

    def publish(self, stamp: Time) -> None:
        odom, stream = self.odometry, self._stream
        self._pub.publish(stream.odometry(stamp, odom.pose, odom.linear, odom.angular))
        if self._tf is not None:
            self._tf.send_transform(stream.transform(stamp, odom.pose))
