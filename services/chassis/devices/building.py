"""The robot in a building (`Floors`, docs/building.md): with ``building:=PATH`` the chassis
loads every floor's map, starts on the floor whose map is ``map``, keeps the landing doors
shut unless the elevator controller reports them open, and moves the robot to another floor
when the car it rides stands there.

Topics: ``/building/elevators/<name>/state`` (zenros_msgs/ElevatorState, latched, from the
controller) in; ``/building/bodies`` (zenros_msgs/BuildingBody: the controller's light
curtain) and ``building/level`` (std_msgs/Int32, latched: the floor the robot is on) out.
The other robots of the building are their ``/building/bodies`` on their floors (the fleet's
shared world, which knows no floors, stands aside in a building).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.building import Building, load_building
from zenros.clock import Time
from zenros.errors import ConfigError
from zenros.msgs.std_msgs import Header, Int32
from zenros.msgs.zenros_msgs import BuildingBody, ElevatorState
from zenros.pubsub import Publisher
from zenros.qos import QOS_LATCHED

from ..device import Chassis, Device, Endpoints
from ..floors import Floors
from ..obstacles import Obstacle, ObstacleError
from ..param_types import Positive
from ..shared_world import BODY_PREFIX, MAX_RADIUS, STALE

__all__ = ["BuildingDevice", "BuildingParameters"]


class BuildingParameters(msgspec.Struct, kw_only=True, frozen=True):
    building: Annotated[str, Meta(
        description="a building file (docs/building.md): the robot starts on the floor whose "
                    "map is `map` and rides its elevators ('' = no building)")] = ""
    building_rate: Annotated[Positive, Meta(
        description="BuildingBody messages per sim second on /building/bodies")] = 10.0


class BuildingDevice(Device[BuildingParameters]):
    Parameters = BuildingParameters
    floors: Floors | None = None
    _bodies: Publisher[BuildingBody]
    _level: Publisher[Int32]

    def __init__(self, params: BuildingParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        if not params.building:
            self.inert = True
            return
        building = load_building(Path(params.building).expanduser())
        level = _start_level(building, chassis.map_path)
        self.floors = Floors(building, chassis.sim.world, level)
        self.rate = params.building_rate
        self._robot = "/"
        self._sent_level: int | None = None
        self._heard: dict[str, float] = {}  # other robots' bodies: when last heard (wall)
        self.refused = 0

    def open(self, node: Endpoints) -> None:
        floors = self.floors
        if floors is None:
            return
        self._robot = node.namespace or "/"
        self._bodies = node.create_publisher(BuildingBody, "/building/bodies")
        self._level = node.create_publisher(Int32, "building/level", QOS_LATCHED)
        for e in floors.building.elevators:
            node.listen(ElevatorState, f"/building/elevators/{e.name}/state", self._on_state,
                        QOS_LATCHED)
        node.listen(BuildingBody, "/building/bodies", self._on_body)

    def _on_body(self, msg: BuildingBody) -> None:
        """Another robot of the building: its body on its floor (as the shared world keeps
        bodies without floors: docs/chassis.md, Several robots in one world)."""
        floors = self.floors
        if floors is None or msg.robot == self._robot:
            return
        ident = BODY_PREFIX + msg.robot
        try:
            if not msg.robot or not 0 < msg.radius <= MAX_RADIUS:
                raise ObstacleError(f"not a robot body: {msg.robot!r} r={msg.radius}")
            floors.building.floor(msg.level)
            body = Obstacle(ident, "circle", msg.x, msg.y, msg.theta, msg.radius)
        except (ObstacleError, LookupError) as exc:
            self.refused += 1
            self.chassis.logger.debug("body refused: %s", exc)
            return
        floors.place_body(ident, msg.level, body)
        self._heard[ident] = time.monotonic()

    def _on_state(self, msg: ElevatorState) -> None:
        if self.floors is not None and not self.floors.on_state(msg):
            self.chassis.logger.warning("elevator state of an elevator the building lacks: %r",
                                        msg.name)

    def step(self, dt: float) -> None:
        if self.floors is None:
            return
        sim = self.chassis.sim
        pose = self.floors.ride(sim.truth)
        if pose is not None:
            sim.truth = pose
            self.chassis.logger.info("rode to level %d: (%.2f, %.2f) on map %s",
                                     self.floors.level, pose.x, pose.y,
                                     self.floors.building.floor(self.floors.level).map_name)

    def changed(self) -> bool:
        return self.floors is not None and self.floors.level != self._sent_level

    def publish(self, stamp: Time) -> None:
        floors = self.floors
        if floors is None:
            return
        now = time.monotonic()
        for ident in [i for i, t in self._heard.items() if now - t > STALE]:
            del self._heard[ident]
            floors.place_body(ident, floors.level, None)
        t = self.chassis.sim.truth
        self._bodies.publish(BuildingBody(
            header=Header(stamp=stamp, frame_id="map"), robot=self._robot, level=floors.level,
            x=t.x, y=t.y, theta=t.theta, radius=self.chassis.sim.radius))
        if floors.level != self._sent_level:
            self._level.publish(Int32(data=floors.level))
            self._sent_level = floors.level


def _start_level(building: Building, map_path: Path) -> int:
    try:
        return building.level_of_map(map_path.stem)
    except LookupError as exc:
        raise ConfigError(f"{exc}: give map:= one of the building's floor maps "
                          f"({', '.join(f.map for f in building.floors)})") from exc
