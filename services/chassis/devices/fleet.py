"""The shared world: this robot's body on ``world_topic``, the other robots' in its world."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.zenros_msgs import Obstacle as ObstacleMsg
from zenros.pubsub import Publisher

from ..device import Chassis, Device, Endpoints
from ..param_types import Positive
from ..shared_world import SharedWorld
from .building import BuildingDevice

__all__ = ["FleetDevice", "FleetParameters"]


class FleetParameters(msgspec.Struct, kw_only=True, frozen=True):
    world_topic: Annotated[str, Meta(
        description="a topic the robots of one simulated world share: this chassis publishes "
                    "its body there and sees the others' in its laser and bumper ('' = alone)"
    )] = ""
    world_rate: Annotated[Positive, Meta(
        description="body messages per sim second on world_topic while the robot moves "
                    "(at rest: every 0.5 s)")] = 10.0


class FleetDevice(Device[FleetParameters]):
    """`SharedWorld` on ``world_topic`` (docs/chassis.md, Several robots in one world);
    with no topic (the default) it does nothing."""

    Parameters = FleetParameters
    shared: SharedWorld | None = None
    _pub: Publisher[ObstacleMsg]

    def __init__(self, params: FleetParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.rate = params.world_rate if params.world_topic else 0.0

    def open(self, node: Endpoints) -> None:
        topic = self.params.world_topic
        if not topic:
            return
        building = self.chassis.device(BuildingDevice)
        if building is not None and building.floors is not None:
            # in a building the others are their /building/bodies, each on its floor
            self.rate = 0.0
            return
        sim = self.chassis.sim
        self.shared = SharedWorld(sim.world, node.namespace, sim.radius)
        self._pub = node.create_publisher(ObstacleMsg, topic)
        node.listen(ObstacleMsg, topic, self.shared.on_body)

    def publish(self, stamp: Time) -> None:
        if self.shared is None:
            return
        body = self.shared.body(self.chassis.sim.truth)
        if self.shared.due(body):
            self._pub.publish(body)
        self.shared.prune()
