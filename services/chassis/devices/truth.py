"""The simulator's ground truth: ``sim/ground_truth`` (nav_msgs/Odometry in ``map``)."""

from __future__ import annotations

from zenros.clock import Time
from zenros.msgs.nav_msgs import Odometry as OdometryMsg
from zenros.pubsub import Publisher

from .. import messages
from ..device import Chassis, Device, Endpoints, NoParameters

__all__ = ["GroundTruthDevice"]


class GroundTruthDevice(Device[NoParameters]):
    """The body's true pose and speeds, every physics step (built only when subscribed)."""

    _pub: Publisher[OdometryMsg]

    def __init__(self, params: NoParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.rate = chassis.step_rate
        self._stream = messages.OdometryStream(chassis.frames.map, chassis.frames.base)

    def open(self, node: Endpoints) -> None:
        self._pub = node.create_publisher(OdometryMsg, "sim/ground_truth")

    def publish(self, stamp: Time) -> None:
        if self._pub.subscription_count:
            sim = self.chassis.sim
            self._pub.publish(self._stream.odometry(stamp, sim.truth, sim.drive.linear,
                                                    sim.drive.angular))
