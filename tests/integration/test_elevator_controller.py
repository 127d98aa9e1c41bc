"""The elevator controller (services/elevator) over real Zenoh: its latched state, the
holder/queue protocol through its command service with bodies published on
``/building/bodies`` (the chassis's side, stood in for here), the light curtain, a dead
holder's lease, sim time, refused and malformed commands, and the process's startup."""

from __future__ import annotations

import json
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import msgspec
import pytest
from tiny_building import CAR, DOORWAY, HALL, write_building
from zenros.clock import Time
from zenros.context import Context
from zenros.msgs.rosgraph_msgs import Clock
from zenros.msgs.zenros_msgs.elevator import (
    BuildingBody,
    ElevatorCommand,
    ElevatorCommandRequest,
    ElevatorCommandResponse,
    ElevatorState,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.rpc import Client
from zenros.services.elevator.node import ElevatorNode, elevator_key
from zenros.testing import Proc, wait_for

STATE = elevator_key("lift1", "state")
COMMAND = elevator_key("lift1", "command")


class Rider:
    """The robots' side: the car's latest state, its command client, a body publisher."""

    def __init__(self, node: Node) -> None:
        self.node = node
        self.states: list[ElevatorState] = []
        self._lock = threading.Lock()
        node.create_subscription(ElevatorState, STATE, self._on_state, QOS_LATCHED)
        self.client: Client[ElevatorCommandRequest, ElevatorCommandResponse] = (
            node.create_client(ElevatorCommand, COMMAND))
        self.bodies = node.create_publisher(BuildingBody, "/building/bodies")
        self.placed: dict[str, BuildingBody] = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._publish_bodies, daemon=True)
        self._thread.start()

    def _publish_bodies(self) -> None:  # 20 Hz, as a chassis near a car
        while not self._stop.wait(0.05):
            with self._lock:
                bodies = list(self.placed.values())
            for b in bodies:
                self.bodies.publish(b)

    def close(self) -> None:
        self._stop.set()
        self._thread.join(5)
        self.node.close()

    def _on_state(self, msg: ElevatorState) -> None:
        with self._lock:
            self.states.append(msg)

    @property
    def state(self) -> ElevatorState:
        with self._lock:
            return self.states[-1] if self.states else ElevatorState()

    def send(self, command: str, robot: str = "", level: int = 0) -> ElevatorCommandResponse:
        req = msgspec.convert({"command": command, "robot": robot, "level": level},
                              ElevatorCommandRequest)
        return self.client.call(req, 5)

    def place(self, robot: str, level: int, at: tuple[float, float]) -> None:
        """``robot``'s body is at ``at`` on ``level`` from now on (published at 20 Hz)."""
        with self._lock:
            self.placed[robot] = BuildingBody(robot=robot, level=level, x=at[0], y=at[1],
                                              radius=0.25)

    def remove(self, robot: str) -> None:
        """``robot``'s body is no longer published (its chassis died)."""
        with self._lock:
            self.placed.pop(robot, None)

    def until(self, pred: Any, timeout: float = 15.0) -> ElevatorState:
        assert wait_for(lambda: pred(self.state), timeout), self.state
        return self.state


@pytest.fixture
def building(tmp_path: Path) -> Path:
    return write_building(tmp_path / "tower")


@pytest.fixture
def controller(ctx_pair: list[Context], building: Path) -> Iterator[ElevatorNode]:
    node = ElevatorNode(context=ctx_pair[0], parameter_overrides={
        "building": str(building), "lease": 0.5})
    yield node
    node.close()


@pytest.fixture
def rider(ctx_pair: list[Context], controller: ElevatorNode) -> Iterator[Rider]:
    node = Node("robots", context=ctx_pair[1])
    r = Rider(node)
    assert r.client.wait_for_service(10)
    r.until(lambda s: s.name == "lift1")
    yield r
    r.close()


def test_the_state_is_latched_for_a_late_subscriber(rider: Rider) -> None:
    s = rider.state
    assert (s.name, s.level, s.position, s.direction, s.state, s.levels, s.capacity) == (
        "lift1", 1, 1.0, "STOP", "NONE", [1, 2, 3], 1)
    assert not s.front_door_open and not s.back_door_open and s.holder == ""


def test_a_robot_calls_enters_rides_and_leaves(rider: Rider) -> None:
    rider.place("robot1", 2, HALL)
    res = rider.send("call", "robot1", 2)
    assert res.success, res.message
    s = rider.until(lambda s: s.state == "WAITING_IN" and s.front_door_open)
    assert (s.level, s.holder) == (2, "robot1")
    rider.place("robot1", 2, CAR)
    rider.until(lambda s: s.riders == ["robot1"])
    assert rider.send("go", "robot1", 3).success
    rider.until(lambda s: s.direction == "UP")
    s = rider.until(lambda s: s.state == "WAITING_OUT" and s.front_door_open)
    assert (s.level, s.holder, s.riders) == (3, "robot1", ["robot1"])
    rider.place("robot1", 3, HALL)
    rider.until(lambda s: s.riders == [])
    assert rider.send("release", "robot1").success
    rider.until(lambda s: s.state == "NONE" and s.holder == "" and s.door == 0.0)


def test_the_doors_wait_for_a_clear_doorway(rider: Rider, controller: ElevatorNode) -> None:
    assert rider.send("call", "robot1", 1).success
    rider.until(lambda s: s.front_door_open)
    rider.place("robot2", 1, DOORWAY)
    rider.until(lambda s: s.door == 1.0)
    # the light curtain has seen robot2 (its body may reach the controller after the "go")
    assert wait_for(lambda: controller.cars["lift1"].blocked, 10)
    assert rider.send("go", "robot1", 2).success
    # four door times: the doors stay open, the car does not leave
    assert not wait_for(lambda: rider.state.door < 1.0 or rider.state.position != 1.0, 2.0)
    rider.place("robot2", 1, HALL)
    rider.until(lambda s: s.state == "WAITING_OUT" and s.level == 2)


def test_a_dead_holder_outside_the_car_loses_its_claim(rider: Rider) -> None:
    rider.place("robot1", 1, HALL)
    assert rider.send("call", "robot1", 1).success
    assert rider.send("call", "robot2", 3).success
    rider.until(lambda s: s.holder == "robot1" and s.queue == ["robot2"] and s.front_door_open)
    rider.remove("robot1")  # its chassis dies: robot2's turn comes after the lease (0.5 s),
    s = rider.until(lambda s: s.holder == "robot2", 10)  # long before hold_s (30 s)
    assert s.queue == []


def test_refused_and_malformed_commands(rider: Rider, ctx_pair: list[Context]) -> None:
    res = rider.send("call", "robot1", 9)
    assert not res.success and "does not serve level 9 (levels 1, 2, 3)" in res.message
    assert rider.send("call", "robot1", 2).success
    res = rider.send("call", "robot1", 3)
    assert not res.success and "already holds" in res.message
    res = rider.send("go", "robot2", 3)
    assert not res.success and "robot2 does not hold lift1" in res.message
    res = rider.send("release", "robot3")
    assert not res.success and "neither holds nor waits" in res.message
    key = ctx_pair[1].keys.service(COMMAND)
    for payload in (b"{", b'{"command": "fly"}', b'{"level": "two"}', b"\xff"):
        replies = list(ctx_pair[1].session.get(key, payload=payload, timeout=5))
        assert len(replies) == 1 and replies[0].err is not None, payload
        assert json.loads(replies[0].err.payload.to_bytes())["error"] == "BadRequest"
    assert rider.send("release", "robot1").success
    # bodies that cannot be bodies are ignored
    rider.bodies.publish(BuildingBody(robot="", level=1))
    rider.bodies.publish(BuildingBody(robot="x", x=float("nan")))
    assert rider.send("to_level", level=3).success
    rider.until(lambda s: s.level == 3 and s.front_door_open)


def test_the_car_runs_on_sim_time(ctx_pair: list[Context], building: Path) -> None:
    """travel_s 4 a floor on a clock run 50x: two floors in well under 8 s of wall time."""
    slow = write_building(building.parent.parent / "slow", travel_s=4.0, door_s=2.0)
    sim = Node("sim", context=ctx_pair[1])
    clock = sim.create_publisher(Clock, "/clock")
    node = ElevatorNode(context=ctx_pair[0], parameter_overrides={
        "building": str(slow), "use_sim_time": True})
    rider = Rider(sim)
    try:
        assert clock.wait_for_subscribers(1, 5) and rider.client.wait_for_service(10)
        t = [1000.0]

        def tick() -> bool:
            t[0] += 0.05
            clock.publish(Clock(clock=Time.from_seconds(t[0])))
            return False

        res = rider.send("to_level", level=3)
        assert not res.success and "has not heard /clock yet" in res.message
        assert wait_for(lambda: tick() or node.now().nanoseconds > 0, 10)
        assert rider.send("to_level", level=3).success
        assert wait_for(lambda: tick() or rider.state.direction == "UP", 10)
        start = t[0]
        assert wait_for(lambda: tick() or rider.state.front_door_open, 20)
        # 2 floors x 4 s + 2 s of doors, in sim seconds (the clock advanced only by us)
        assert t[0] - start == pytest.approx(8.0 + 2.0, abs=0.6)
    finally:
        node.close()
        rider.close()


def test_the_process_starts_with_a_building_and_refuses_without(
        router: str, prefix: str, procs: list[Proc], building: Path,
        observer: Context) -> None:
    base = [sys.executable, "-m", "zenros.services.elevator", "-e", router,
            "--prefix", prefix]
    bare = Proc(base)
    procs.append(bare)
    assert bare.wait(20) == 3
    assert "no building: give the building YAML" in bare.output
    proc = Proc([*base, "-p", f"building:={building}"])
    procs.append(proc)
    rider = Rider(Node("watcher", context=observer))
    try:
        assert rider.client.wait_for_service(20), proc.output
        rider.until(lambda s: s.levels == [1, 2, 3])
        assert rider.send("to_level", level=2).success
        rider.until(lambda s: s.level == 2 and s.front_door_open)
    finally:
        rider.close()
    assert proc.stop() == 0, proc.output
