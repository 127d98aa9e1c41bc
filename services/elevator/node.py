"""`ElevatorNode`: the building's elevator controller on Zenoh: one `Car` per elevator of
the building file, stepped on the node's clock (sim time under ``use_sim_time``).

Parameters: ``building`` (the building YAML, zenros.building; required), ``rate`` (steps a
second, 20), ``lease`` (s of silence on ``/building/bodies``, on both the node's clock and
the wall, after which a holder outside its car loses its claim; 5). Endpoints, absolute so
every robot's namespace reaches them (zenros_msgs/elevator.py): per elevator
``/building/elevators/<name>/state`` (latched; on every change and at 2 Hz) and
``/building/elevators/<name>/command`` (a service); ``/building/bodies`` in.
docs/building.md, "The elevator controller".
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Annotated

import msgspec
from msgspec import Meta
from zenros import Node
from zenros.building import Building, load_building
from zenros.errors import ConfigError
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs.elevator import (
    BuildingBody,
    ElevatorCommand,
    ElevatorCommandRequest,
    ElevatorCommandResponse,
    ElevatorState,
)
from zenros.pubsub import Publisher
from zenros.qos import QOS_LATCHED

from .bodies import BodyTable, body_of
from .car import Car
from .commands import execute

__all__ = ["ElevatorNode", "ElevatorParameters", "elevator_key"]

STATE_PERIOD = 0.5  # s between two publications of an unchanged state (2 Hz)


def elevator_key(name: str, what: str) -> str:
    """The absolute name of elevator ``name``'s ``state`` topic or ``command`` service."""
    return f"/building/elevators/{name}/{what}"


class ElevatorParameters(msgspec.Struct, kw_only=True, frozen=True):
    building: Annotated[str, Meta(description=(
        "the building YAML (floors and elevators; docs/building.md)"))] = ""
    rate: Annotated[float, Meta(gt=0, le=200, description="car steps a second")] = 20.0
    lease: Annotated[float, Meta(gt=0, description=(
        "s of silence on /building/bodies (node clock and wall both) after which a holder "
        "outside its car loses its claim"))] = 5.0


class _Outlet:
    """One car's state publisher: on every change, and at least every STATE_PERIOD s."""

    def __init__(self, pub: Publisher[ElevatorState]) -> None:
        self.pub = pub
        self.last: ElevatorState | None = None
        self.at = -float("inf")

    def offer(self, state: ElevatorState, node: Node, now: float) -> None:
        if state == self.last and now - self.at < STATE_PERIOD:
            return
        self.last, self.at = state, now
        stamped = msgspec.structs.replace(state, header=Header(stamp=node.now(),
                                                               frame_id=""))
        self.pub.publish(stamped)


class ElevatorNode(Node):
    node_name = "elevator_controller"

    def setup(self) -> None:
        self.params = self.declare_parameters(ElevatorParameters, read_only=True)
        self.building = self._load(self.params.building)
        self.bodies = BodyTable(self.params.lease)
        self._lock = threading.Lock()
        now = self._now()
        self.cars = {e.name: Car(e, now) for e in self.building.elevators}
        self.outlets: dict[str, _Outlet] = {}
        for name in self.cars:
            self.outlets[name] = _Outlet(self.create_publisher(
                ElevatorState, elevator_key(name, "state"), QOS_LATCHED))
            self.create_service(ElevatorCommand, elevator_key(name, "command"),
                                self._handler(name))
        self.create_subscription(BuildingBody, "/building/bodies", self.on_body)
        self.create_timer(1.0 / self.params.rate, self.on_tick)
        if not self.cars:
            self.logger.warning("building %r has no elevator: nothing to control",
                                self.building.name)
        self.logger.info("building %r: elevator(s) %s", self.building.name,
                         ", ".join(f"{n} (levels {c.spec.levels})" for n, c in self.cars.items())
                         or "none")
        self._publish(now, force=True)

    @staticmethod
    def _load(path: str) -> Building:
        if not path:
            raise ConfigError("no building: give the building YAML, -p building:=PATH "
                              "(docs/building.md)")
        return load_building(path)

    def _now(self) -> float:
        return self.now().nanoseconds / 1e9

    def on_body(self, msg: BuildingBody) -> None:
        body = body_of(msg)
        if body is None:
            self.logger.debug("ignored a body on /building/bodies: %r", msg)
            return
        with self._lock:
            self.bodies.heard(body, self._now(), time.monotonic())

    def _waiting_for_clock(self) -> bool:
        """Under use_sim_time, no /clock heard yet (the node's time is 0)."""
        return self.now().nanoseconds == 0

    def on_tick(self) -> None:
        if self._waiting_for_clock():
            return
        with self._lock:
            now, wall = self._now(), time.monotonic()
            live, lost = self.bodies.live(now, wall), self.bodies.lost(now, wall)
            for car in self.cars.values():
                car.step(now, live, lost)
                for event in car.events:
                    self.logger.info("%s", event)
                car.events.clear()
            self._publish(now)

    def _publish(self, now: float, force: bool = False) -> None:
        for name, car in self.cars.items():
            outlet = self.outlets[name]
            if force:
                outlet.last = None
            outlet.offer(car.snapshot(), self, now)

    def _handler(self, name: str) -> Callable[[ElevatorCommandRequest], ElevatorCommandResponse]:
        def handle(req: ElevatorCommandRequest) -> ElevatorCommandResponse:
            if self._waiting_for_clock():
                return ElevatorCommandResponse(message=(
                    "the elevator controller runs on sim time (use_sim_time) and has not "
                    "heard /clock yet"))
            with self._lock:
                now = self._now()
                car = self.cars[name]
                res = execute(car, req, now)
                self.logger.info("%s %s: %s", name, req.command,
                                 res.message if res.success else f"refused: {res.message}")
                self._publish(now)
            return res
        return handle
