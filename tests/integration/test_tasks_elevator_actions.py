"""The elevator task actions (docs/tasks.md, "Elevator actions") through a real tasks service
and the building's elevator controller over Zenoh: ``elevator_req_action`` calls the car and
completes once it stands open at the floor for the robot, a cancel or the task's end releases
the claim; ``lbt_elevator_req_action`` and ``lbt_elevator_ack_action`` ride the car through the
controller's holder protocol; unserved levels, a missing request and a timeout are errors."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from tiny_building import write_building
from zenros.context import Context
from zenros.msgs.zenros_msgs import ElevatorState, ResultCode
from zenros.msgs.zenros_msgs.tasks import TASK_SERVICES, response_data, task_request
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.services.elevator.node import ElevatorNode, elevator_key
from zenros.services.tasks.node import TasksNode
from zenros.testing import wait_for

ENDED = ("COMPLETE", "ERROR", "FAILED", "CANCELLED")


class User:
    """The tasks service's calls and the car's latched state, from a node of its own."""

    def __init__(self, node: Node) -> None:
        self.node = node
        self.clients: dict[str, Any] = {}
        self.car = ElevatorState()
        self.seen: list[ElevatorState] = []
        node.create_subscription(ElevatorState, elevator_key("lift1", "state"),
                                 self._on_state, QOS_LATCHED)

    def _on_state(self, msg: ElevatorState) -> None:
        self.car = msg
        self.seen.append(msg)

    def call(self, name: str, id: str = "", body: Any = None) -> Any:
        if name not in self.clients:
            self.clients[name] = self.node.create_client(TASK_SERVICES[name], f"/tasks/{name}")
            assert self.clients[name].wait_for_service(10)
        r = self.clients[name].call(task_request(name, id, body), timeout=20)
        assert r.code == ResultCode.OK, r.message
        return response_data(r, single=bool(id))

    def run(self, *actions: dict[str, Any], timeout: float = 40) -> dict[str, Any]:
        """Create and start a task of ``actions``; the task once it has ended."""
        task = self.call("create", body={"name": "lift", "sub_tasks": list(actions)})
        self.call("start", task["id"])
        got: list[dict[str, Any]] = []

        def ended() -> bool:
            got.append(self.call("get", task["id"]))
            return got[-1]["state"] in ENDED
        assert wait_for(ended, timeout, interval=0.1), got[-1:]
        return got[-1]


@pytest.fixture
def user(ctx_pair: list[Context], tmp_path: Path) -> Iterator[User]:
    building = write_building(tmp_path / "tower", travel_s=2.0)
    lift = ElevatorNode(context=ctx_pair[0], parameter_overrides={"building": str(building)})
    tasks = TasksNode(context=ctx_pair[1], parameter_overrides={
        "data_dir": str(tmp_path / "t"), "building": str(building)})
    node = Node("user", context=ctx_pair[0])
    try:
        u = User(node)
        assert wait_for(lambda: u.car.name == "lift1", 10)
        yield u
    finally:
        node.close()
        tasks.close()
        lift.close()


def test_elevator_req_calls_the_car_and_the_tasks_end_releases_it(user: User) -> None:
    done = user.run({"type": "elevator_req_action", "level": 2, "direction": "up"})
    assert done["state"] == "COMPLETE", done
    result = done["sub_tasks"][0]["result"]
    assert "elevator lift1 open at level 2" in result and "up" in result, result
    held = [s for s in user.seen if s.holder == "/" and s.door == 1.0]
    assert held and (held[0].level, held[0].state) == (2, "WAITING_IN"), user.seen
    # nothing used the claim: the task's end gave it back
    assert wait_for(lambda: user.car.holder == "" and user.car.level == 2, 10), user.car


def test_an_elevator_req_that_cannot_be_served_is_an_error(user: User) -> None:
    done = user.run({"type": "elevator_req_action", "level": 7})
    assert done["state"] == "ERROR"
    assert "lift1 does not serve level 7 (levels 1, 2, 3)" in done["sub_tasks"][0]["result"]
    done = user.run({"type": "elevator_req_action", "level": 2, "elevator_name": "lift9"})
    assert "unknown elevator 'lift9'" in done["sub_tasks"][0]["result"], done
    done = user.run({"type": "elevator_req_action", "level": 3, "timeout": 0.5})
    assert done["state"] == "ERROR"
    assert "timed out waiting for elevator lift1 open at level 3" in done["sub_tasks"][0][
        "result"], done
    assert wait_for(lambda: user.car.holder == "" and not user.car.calls, 10), user.car


def test_a_cancelled_elevator_req_releases_the_claim(user: User) -> None:
    task = user.call("create", body={"sub_tasks": [{"type": "elevator_req_action",
                                                    "level": 3}]})
    user.call("start", task["id"])
    assert wait_for(lambda: user.car.holder == "/" and user.car.direction == "UP", 10), user.car
    user.call("stop", task["id"])
    assert user.call("get", task["id"])["state"] == "CANCELLED"
    assert wait_for(lambda: user.car.holder == "", 10), user.car


def test_lbt_enter_ack_leave_ack_rides_the_car(user: User) -> None:
    done = user.run(
        {"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 3, "cmd": "enter"},
        {"type": "lbt_elevator_ack_action"},
        {"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 3, "cmd": "leave"},
        {"type": "lbt_elevator_ack_action"})
    assert done["state"] == "COMPLETE", [(a["state"], a["result"]) for a in done["sub_tasks"]]
    results = [a["result"] for a in done["sub_tasks"]]
    assert "open at level 1" in results[0] and "takes / to level 3" in results[1], results
    assert "open at level 3" in results[2] and "pose is unknown" in results[2], results
    assert "released lift1" in results[3], results
    opened = [(s.state, s.level) for s in user.seen if s.door == 1.0 and s.state != "NONE"]
    assert opened[:1] == [("WAITING_IN", 1)] and ("WAITING_OUT", 3) in opened, user.seen
    assert wait_for(lambda: user.car.holder == "" and user.car.level == 3, 10), user.car


def test_an_ack_with_no_request_and_a_leave_before_its_time_are_errors(user: User) -> None:
    done = user.run({"type": "lbt_elevator_ack_action"})
    assert done["state"] == "ERROR"
    assert "nothing to acknowledge" in done["sub_tasks"][0]["result"]
    done = user.run({"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 2,
                     "cmd": "leave"})
    assert done["state"] == "ERROR"
    assert "does not hold elevator lift1" in done["sub_tasks"][0]["result"], done
    done = user.run(
        {"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 2, "cmd": "enter"},
        {"type": "lbt_elevator_req_action", "from_level": 1, "to_level": 2, "cmd": "leave"})
    assert done["state"] == "ERROR"
    assert "still waits at level 1 for this robot to enter" in done["sub_tasks"][1]["result"]
    assert wait_for(lambda: user.car.holder == "", 10), user.car  # the task's end
