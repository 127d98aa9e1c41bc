"""One gateway for a fleet: the robot API of each robot under /api/v1/robots/<name>/, the
single-robot paths for the default robot, GET /api/v1/robots, the topic WebSocket per robot,
robots found in the graph; each robot's paths reach that robot's topics only."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
import websockets
from websockets.asyncio.client import connect
from zenros.context import Context
from zenros.errors import ConfigError
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.sensor_msgs import BatteryState
from zenros.msgs.zenros_msgs import ChassisState
from zenros.node import Node
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway
from zenros.testing import Collector, wait_for

ROBOTS = ("robot1", "robot2", "robot3")
VOLTS = {"robot1": 24.0, "robot2": 30.0, "robot3": 36.0}


@pytest.fixture
def gw(ctx_pair: list[Context], tmp_path: Path) -> Iterator[GatewayNode]:
    with running_gateway(ctx_pair[0], tmp_path, robots=list(ROBOTS)) as node:
        yield node


@pytest.fixture
def http(gw: GatewayNode) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=10) as c:
        yield c


@pytest.fixture
def token(http: httpx.Client) -> str:
    r = http.get("/robots/robot2/token", params={"username": "admin", "password": "admin"})
    assert r.status_code == 200, r.text
    return str(r.json()["token"])


def feed_batteries(fleet: Node) -> None:
    """Each robot's battery_state, a voltage of its own, until the test ends."""
    pubs = {n: fleet.create_publisher(BatteryState, f"/{n}/battery_state", 10) for n in ROBOTS}
    assert all(p.wait_for_subscribers(1, 5) for p in pubs.values())
    fleet.create_timer(0.05, lambda: [p.publish(BatteryState(voltage=VOLTS[n], percentage=VOLTS[n]
                                                             / 40)) for n, p in pubs.items()])


def test_each_robot_answers_under_its_name_and_the_default_at_the_old_paths(
        gw: GatewayNode, http: httpx.Client, token: str, make_node: object) -> None:
    assert gw.fleet is not None and list(gw.robots) == list(ROBOTS)
    assert gw.fqn == "/gateway"
    assert {r.core.identity.id for r in gw.robots.values()}.__len__() == 3
    feed_batteries(make_node("fleet", 1))  # type: ignore[operator]

    def power(path: str) -> float:
        r = http.get(f"{path}/system/galileo_status", params={"token": token})
        assert r.status_code == 200, r.text
        return float(r.json()["power"])

    assert wait_for(lambda: all(power(f"/robots/{n}") == VOLTS[n] for n in ROBOTS), 10)
    assert power("") == VOLTS["robot1"]  # the single-robot paths: the default robot
    listed = http.get("/robots", params={"token": token}).json()
    assert listed["default"] == "robot1"
    assert [r["name"] for r in listed["robots"]] == list(ROBOTS)
    assert {r["name"]: r["battery"] for r in listed["robots"]} == {
        n: pytest.approx(VOLTS[n] / 40 * 100, abs=0.1) for n in ROBOTS}
    assert all({"state", "estop", "pose", "online", "charging"} <= set(r)
               for r in listed["robots"])
    # every operation of the single-robot API is there per robot (the same handlers)
    ops = http.get("/robots/robot3/").json()["implemented"]
    assert ops == [op.replace("/api/v1/", "/api/v1/robots/robot3/", 1)
                   for op in http.get("/").json()["implemented"]]
    assert "POST /api/v1/robots/robot3/navigation/start_nav_task" in ops
    assert http.get("/robots/robot3/system/status", params={"token": token}).json() == \
        {"status": "Free"}


def test_tokens_unknown_robots_and_unknown_paths(gw: GatewayNode, http: httpx.Client,
                                                 token: str) -> None:
    for path in ("/robots", "/robots/robot3/system/status", "/system/status"):
        r = http.get(path)
        assert r.status_code == 401 and "missing token" in r.json()["description"], path
    assert http.get("/robots", params={"token": "0" * 32}).status_code == 401
    r = http.get("/robots/robot9/system/status", params={"token": token})
    assert r.status_code == 404
    assert r.json() == {"status": "error", "description":
                        "no robot 'robot9' on this gateway (GET /api/v1/robots lists its robots)"}
    r = http.get("/robots/robot2/no/such/thing", params={"token": token})
    assert r.status_code == 404
    assert r.json()["description"] == "no such endpoint: /api/v1/robots/robot2/no/such/thing"
    assert http.post("/robots", params={"token": token}).status_code == 405
    assert http.get("/robots", params={"token": token, "x": "1"}).status_code == 400


def test_a_command_reaches_its_own_robot_only(gw: GatewayNode, http: httpx.Client, token: str,
                                              make_node: object) -> None:
    fleet = make_node("fleet", 1)  # type: ignore[operator]
    got = {n: Collector[Twist]() for n in ROBOTS}
    for n in ROBOTS:
        fleet.create_subscription(Twist, f"/{n}/cmd_vel", got[n], 50)
    assert all(gw.robots[n].topics.cmd_vel_pub.wait_for_subscribers(1, 5) for n in ROBOTS)
    r = http.put("/robots/robot2/system/speed", params={"token": token},
                 json={"speed_x": 0.3, "speed_y": 0, "speed_angle": 0})
    assert r.json() == {"result": True}
    assert got["robot2"].wait(1, 5) and got["robot2"].items[0].linear.x == 0.3
    r = http.put("/system/speed", params={"token": token},
                 json={"speed_x": 0.1, "speed_y": 0, "speed_angle": 0})
    assert r.json() == {"result": True}
    assert got["robot1"].wait(1, 5) and got["robot1"].items[0].linear.x == 0.1
    assert all(t.linear.x == 0.3 for t in got["robot2"].items if t.linear.x)
    assert not [t for t in got["robot3"].items if t.linear.x]
    # a robot's e-stop shows in the list, for that robot alone
    states = {n: fleet.create_publisher(ChassisState, f"/{n}/chassis/state", 10)
              for n in ROBOTS}
    assert all(p.wait_for_subscribers(1, 5) for p in states.values())

    def estops() -> dict[str, bool]:
        robots = http.get("/robots", params={"token": token}).json()["robots"]
        return {r["name"]: r["estop"] for r in robots}

    assert wait_for(lambda: [p.publish(ChassisState(estop=n == "robot3"))
                             for n, p in states.items()]
                    and estops() == {"robot1": False, "robot2": False, "robot3": True}, 5)


async def test_topic_websocket_per_robot(gw: GatewayNode, token: str,
                                         make_node: object) -> None:
    feed_batteries(make_node("fleet", 1))  # type: ignore[operator]
    base = f"ws://127.0.0.1:{gw.ws_port}"
    for path, volts in (("robots/robot3/battery_state", 36.0), ("battery_state", 24.0)):
        async with connect(f"{base}/{path}?token={token}") as ws:
            assert json.loads(await asyncio.wait_for(ws.recv(), 5))["voltage"] == volts
    with pytest.raises(websockets.InvalidStatus) as info:
        async with connect(f"{base}/robots/robot9/battery_state?token={token}"):
            pass
    assert info.value.response.status_code == 404
    assert b"no robot 'robot9'" in info.value.response.body


def test_robots_found_in_the_graph(ctx_pair: list[Context], tmp_path: Path,
                                   make_node: object) -> None:
    with running_gateway(ctx_pair[0], tmp_path, discover_robots=True, default_robot="robot1",
                         no_token_check=True) as gw:
        base = f"http://127.0.0.1:{gw.rest_port}/api/v1"

        def names() -> list[str]:
            return [r["name"] for r in httpx.get(f"{base}/robots").json()["robots"]]

        assert names() == ["robot1"]  # the default is served before it shows up
        make_node("chassis", 1, namespace="/robot7")  # type: ignore[operator]
        # not robots: a namespace of two chunks, a namespace without a chassis
        make_node("chassis", 1, namespace="/site/robot8")  # type: ignore[operator]
        make_node("nav", 1, namespace="/robot9")  # type: ignore[operator]
        assert wait_for(lambda: names() == ["robot1", "robot7"], 10), names()
        assert gw.graph.wait_for(lambda: "/robot7/gateway" in gw.graph.node_names(), 5)
        r = httpx.get(f"{base}/robots/robot7/system/status")
        assert r.json() == {"status": "Free"}


def test_a_robot_that_could_not_be_built_is_served_at_a_later_look(
        ctx_pair: list[Context], tmp_path: Path, make_node: object,
        monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture) -> None:
    """Each graph change asks for a look, and the gateway also looks every LOOK_PERIOD: a
    robot whose first build failed (or whose change was missed) is served at a later look,
    and the failure is logged once, not at every look."""
    from zenros.services.gateway import fleet

    builds: list[str] = []
    real = fleet.RobotView

    def flaky(namespace: str, *args: object, **kwargs: object) -> object:
        builds.append(namespace)
        if namespace == "/robot7" and builds.count("/robot7") <= 3:
            raise RuntimeError("robot7's first builds fail")
        return real(namespace, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(fleet, "RobotView", flaky)
    with running_gateway(ctx_pair[0], tmp_path, discover_robots=True, default_robot="robot1",
                         no_token_check=True) as gw:
        base = f"http://127.0.0.1:{gw.rest_port}/api/v1"

        def names() -> list[str]:
            return [r["name"] for r in httpx.get(f"{base}/robots").json()["robots"]]

        make_node("chassis", 1, namespace="/robot7")  # type: ignore[operator]
        assert wait_for(lambda: names() == ["robot1", "robot7"], 10 + 4 * fleet.LOOK_PERIOD), \
            (names(), builds)
        assert builds.count("/robot7") == 4, builds  # three failed, the fourth served it
    failures = [r for r in caplog.records if "cannot serve robot robot7" in r.getMessage()]
    assert len(failures) == 1, [r.getMessage() for r in failures]


@pytest.mark.parametrize(("params", "words"), [
    ({"robots": ["robot1", "a/b"]}, "robot name 'a/b': expected a namespace of one chunk"),
    ({"robots": ["robot 1"]}, "robot name 'robot 1'"),
    ({"robots": [3]}, "robot name 3"),
    ({"discover_robots": True}, "discover_robots without default_robot"),
    ({"default_robot": "robot2"}, "default_robot is set, but neither robots nor"),
])
def test_bad_fleet_configuration_is_refused(ctx_pair: list[Context], tmp_path: Path,
                                            params: dict[str, object], words: str) -> None:
    with pytest.raises(ConfigError, match=words.replace("(", r"\(")), \
            running_gateway(ctx_pair[0], tmp_path, **params):
        pass


def test_default_robot_chosen(ctx_pair: list[Context], tmp_path: Path) -> None:
    with running_gateway(ctx_pair[0], tmp_path, robots=["robot1", "robot2"],
                         default_robot="/robot2", no_token_check=True) as gw:
        assert gw.core is gw.robots["robot2"].core and list(gw.robots) == ["robot1", "robot2"]
        base = f"http://127.0.0.1:{gw.rest_port}"
        assert httpx.get(f"{base}/api/v1/robots").json()["default"] == "robot2"
        config = httpx.get(f"{base}/config.json").json()  # the dashboard's fleet view
        assert config["namespace"] == "/robot2" and config["robots"] == ["robot1", "robot2"]
