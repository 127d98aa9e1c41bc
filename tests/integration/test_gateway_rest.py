"""The gateway's REST API: token, system, errors, 501s.

Tests that need the real door (uvicorn on a socket, the robot's topics) get a gateway of their
own (``gw``/``http``); pure request-validation cases share one gateway per module and call its
ASGI app in process (``app``: `AsgiClient`, httpx's ASGI transport, no socket), which answers exactly as
the socket does (the same `HttpApp`)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
from zenros.context import Context
from zenros.msgs.galileo_msgs import GalileoStatus
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.sensor_msgs import BatteryState
from zenros.services.gateway.http.spec_routes import SPEC_OPERATIONS
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import AsgiClient, running_gateway
from zenros.testing import Collector, linked_contexts, wait_for


@pytest.fixture
def gw(ctx_pair: list[Context], tmp_path: Path) -> Iterator[GatewayNode]:
    with running_gateway(ctx_pair[0], tmp_path) as node:
        yield node


@pytest.fixture
def http(gw: GatewayNode) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=5) as c:
        yield c


def _login(client: httpx.Client | AsgiClient) -> str:
    r = client.get("/token", params={"username": "admin", "password": "admin"})
    assert r.status_code == 200
    body = r.json()
    assert body["result"] is True and len(body["token"]) == 32
    return str(body["token"])


@pytest.fixture
def token(http: httpx.Client) -> str:
    return _login(http)


@pytest.fixture(scope="module")
def module_gw(tmp_path_factory: pytest.TempPathFactory) -> Iterator[GatewayNode]:
    """One gateway for the module's request-validation cases (they change no state)."""
    with linked_contexts(1) as (ctx,), running_gateway(
            ctx, tmp_path_factory.mktemp("gw")) as node:
        yield node


@pytest.fixture(scope="module")
def app(module_gw: GatewayNode) -> AsgiClient:
    """The shared gateway's REST app called in process (ASGI), under ``/api/v1``."""
    return AsgiClient(module_gw.http, "/api/v1")


@pytest.fixture(scope="module")
def app_token(app: AsgiClient) -> str:
    return _login(app)


def assert_error(r: httpx.Response, code: int, *words: str) -> None:
    assert r.status_code == code, r.text
    body = r.json()
    assert body.get("status") == "error" or body.get("result") is False, body
    for w in words:
        assert w in body["description"], body


def test_token_required_and_checked(http: httpx.Client, token: str) -> None:
    assert_error(http.get("/system/status"), 401, "missing token")
    assert_error(http.get("/system/status", params={"token": "0" * 32}), 401, "invalid token")
    assert_error(http.get("/token", params={"username": "admin", "password": "x"}), 401,
                 "wrong username or password")
    r = http.get("/system/status", params={"token": token})
    assert r.json() == {"status": "Free"}
    # POST/PUT may carry the token in the body
    r = http.put("/system/speed", json={"token": token, "speed_x": 0.0})
    assert r.json() == {"result": True}


def test_no_token_check_from_config_file(ctx_pair: list[Context], tmp_path: Path) -> None:
    (tmp_path / "config.json").write_text('{"no_token_check": true, "password": "pw"}')
    with running_gateway(ctx_pair[0], tmp_path) as node:
        base = f"http://127.0.0.1:{node.rest_port}/api/v1"
        assert httpx.get(f"{base}/system/status").json() == {"status": "Free"}
        r = httpx.get(f"{base}/token", params={"username": "admin", "password": "pw"})
        assert r.json()["result"] is True


def test_galileo_status_follows_live_topics(gw: GatewayNode, http: httpx.Client, token: str,
                                            make_node: object) -> None:
    robot = make_node("fake_robot", 1)  # type: ignore[operator]
    odom = robot.create_publisher(Odometry, "odom", 10)
    batt = robot.create_publisher(BatteryState, "battery_state", 10)
    seen: Collector[GalileoStatus] = Collector()
    robot.create_subscription(GalileoStatus, "galileo/status", seen, 10)
    assert odom.wait_for_subscribers(1, 5) and batt.wait_for_subscribers(1, 5)
    msg = Odometry()
    msg.twist.twist.linear.x = 0.25
    msg.twist.twist.angular.z = -0.5
    assert wait_for(lambda: (odom.publish(msg), batt.publish(
        BatteryState(voltage=37.05, percentage=0.8)))
        and gw.core.status.power > 37 and gw.core.status.currentSpeedX == 0.25, 5)
    st = http.get("/system/galileo_status", params={"token": token}).json()
    assert st["power"] == pytest.approx(37.05) and st["currentSpeedTheta"] == -0.5
    assert st["header"]["frame_id"] == "map" and {"secs", "nsecs"} <= set(st["header"]["stamp"])
    assert set(st) == set(GalileoStatus.__struct_fields__)
    assert seen.wait(3) and seen.items[-1].header.seq > 0
    sp = http.get("/system/speed", params={"token": token}).json()
    assert sp == {"speed_x": 0.25, "speed_y": 0.0, "speed_angle": -0.5}
    info = http.get("/system/info", params={"token": token}).json()
    assert info["battery"] == 80 and info["info"]["port"] == gw.rest_port
    assert {"camera_rgb", "odom", "imu", "driver_port", "charge", "loop", "slam_type"} <= set(info)


def test_put_speed_publishes_cmd_vel_with_deadman(gw: GatewayNode, http: httpx.Client,
                                                  token: str, make_node: object) -> None:
    base = make_node("fake_base", 1)  # type: ignore[operator]
    got: Collector[Twist] = Collector()
    base.create_subscription(Twist, "cmd_vel", got, 50)
    assert gw.topics.cmd_vel_pub.wait_for_subscribers(1, 5)
    r = http.put("/system/speed", params={"token": token},
                 json={"speed_x": 0.3, "speed_y": 0, "speed_angle": 0.2})
    assert r.json() == {"result": True}
    assert got.wait(1, 3) and got.items[0].linear.x == 0.3 and got.items[0].angular.z == 0.2
    # silence: the dead-man sends one stop, then nothing
    assert wait_for(lambda: got.items[-1].linear.x == 0.0, 3)
    n = len(got.items)
    assert not wait_for(lambda: len(got.items) > n, 0.3)
    # the dead-man's ticker stopped at rest; the next command starts it again, held while
    # repeated, and stopped once more after the silence
    assert gw.topics._deadman_timer.is_canceled()
    for _ in range(3):
        r = http.put("/system/speed", params={"token": token},
                     json={"speed_x": -0.1, "speed_y": 0, "speed_angle": 0.0})
        assert r.json() == {"result": True}
    assert got.wait(n + 2, 3) and got.items[n].linear.x == -0.1
    assert wait_for(lambda: len(got.items) > n + 4 and got.items[-1].linear.x == 0.0, 3)
    assert [m.linear.x for m in got.items[n:]].count(0.0) == 1
    assert wait_for(lambda: gw.topics._deadman_timer.is_canceled(), 1)


def test_config_get_post_delete(http: httpx.Client, token: str) -> None:
    t = {"token": token}
    cfg = http.get("/system/config", params=t).json()
    assert {"default_map", "maps", "auto_charge", "go_charge_percentage"} <= set(cfg)
    r = http.post("/system/config", params=t, json={"auto_charge": True,
                                                     "go_charge_percentage": 30})
    assert r.json()["auto_charge"] is True and r.json()["go_charge_percentage"] == 30
    assert http.get("/system/config", params=t).json()["auto_charge"] is True
    assert http.delete("/system/config", params={**t, "key": "auto_charge"}).json() == {
        "status": "ok"}
    assert http.get("/system/config", params=t).json()["auto_charge"] is False
    assert_error(http.delete("/system/config", params={**t, "key": "nope"}), 400, "nope")


@pytest.mark.parametrize("body, words", [
    (b'{"speed_x": 0.1', ["malformed JSON"]),
    (b'[1, 2]', ["must be an object"]),
    (b'{"speed_x": "fast"}', ["speed_x", "float"]),
    (b'{"speed_x": 0.1, "turbo": true}', ["unknown field", "turbo"]),
    (b'{"speed_x": 50}', ["speed_x", "<="]),
    (b'{"speed_x": NaN}', ["malformed JSON"]),
    (b"{\"speed_angle\": -1e400}", ["out of range"]),
    (b'{"speed_x": ' + b"[" * 3000 + b"]" * 3000 + b"}", ["malformed JSON", "deep"]),
])
def test_bad_bodies_get_4xx(app: AsgiClient, app_token: str, body: bytes,
                            words: list[str]) -> None:
    r = app.put("/system/speed", params={"token": app_token}, content=body,
                headers={"content-type": "application/json"})
    assert_error(r, 400, *words)


def test_bad_queries_oversize_and_unknown_paths(app: AsgiClient, app_token: str) -> None:
    http, t = app, {"token": app_token}
    assert_error(http.get("/system/status", params={**t, "x": "1"}), 400, "unknown query", "x")
    assert_error(http.post("/system/config", params=t, content=b"{" + b" " * 70000 + b"}",
                           headers={"content-type": "application/json"}), 413, "too large")
    assert_error(http.get("/no/such/thing", params=t), 404, "no such endpoint")
    assert_error(http.post("/system/status", params=t, json={}), 405, "GET")
    assert_error(http.post("/system/config", params=t, json={"navigation_speed": "x"}), 400,
                 "navigation_speed")


def test_every_spec_operation_is_routed(http: httpx.Client, token: str) -> None:
    index = http.get("/").json()
    listed = set(index["implemented"]) | set(index["not_implemented"])
    for method, path in SPEC_OPERATIONS:
        assert f"{method} /api/v1{path}" in listed
    for entry in index["not_implemented"]:
        method, url = entry.split(" ", 1)
        url = url.replace("{file_timestamp}", "123")
        r = http.request(method, url.removeprefix("/api/v1"), params={"token": token})
        assert r.status_code == 501, entry
        assert r.json() == {"status": "error",
                            "description": f"not implemented: {url}"}


def test_openapi_matches_routes(http: httpx.Client) -> None:
    doc = http.get("/openapi.json").json()
    index = http.get("/").json()
    ops = {f"{m.upper()} {p}" for p, item in doc["paths"].items() for m in item}
    assert ops == set(index["implemented"]) | set(index["not_implemented"])
    speed = doc["paths"]["/api/v1/system/speed"]["put"]
    ref = speed["requestBody"]["content"]["application/json"]["schema"]["$ref"]
    body = doc["components"]["schemas"][ref.rsplit("/", 1)[1]]
    assert set(body["properties"]) == {"speed_x", "speed_y", "speed_angle"}
    assert "501" not in speed["responses"] and "401" in speed["responses"]
    for op in index["not_implemented"]:  # whatever still answers 501 says so
        method, path = op.split(" ", 1)
        assert "501" in doc["paths"][path][method.lower()]["responses"]


HOSTILE_BODIES = [b"{", b"[]", b'"x"', b"null", b'{"a": ' * 200 + b"1" + b"}" * 200,
                  b'{"x": "1e999999", "index": -5, "map_name": "../../etc/passwd"}',
                  b'{"speed_x": [1, 2], "type": 7, "path_data": 5}', b"\xff\xfe\x00"]
HOSTILE_QUERIES = [{"id": "x" * 500}, {"index": "NaN"}, {"map_name": "../x"},
                   {"name": "a/b"}, {"loop_flag": "2"}, {"text": ""}, {"unknown": "1"},
                   {"topic_name": "$$$"}, {"param": "/../x"}, {"key": "\x00"}]


def assert_no_500(http: httpx.Client, entry: str, token: dict[str, str]) -> None:
    """``entry`` (``"GET /api/v1/..."``), fed hostile queries (and bodies, for POST and PUT),
    answers a docs/robot-api.md §1.2 body with a code other than 500."""
    method, url = entry.split(" ", 1)
    path = url.removeprefix("/api/v1")
    tries: list[tuple[dict[str, str], bytes | None]] = [(token, None)] + [
        ({**token, **q}, None) for q in HOSTILE_QUERIES]
    if method in ("POST", "PUT"):
        tries += [(token, b) for b in HOSTILE_BODIES]
    for params, body in tries:
        r = http.request(method, path, params=params, content=body,
                         headers={"content-type": "application/json"})
        assert r.status_code != 500, (entry, params, body, r.text)
        if r.status_code >= 400:
            err = r.json()
            assert err.get("status") == "error" or err.get("result") is False, err
            assert err["description"], err


def test_no_input_gets_a_500(http: httpx.Client, token: str) -> None:
    """Every implemented operation, fed hostile bodies and queries, answers a docs/robot-api.md §1.2
    body with a code other than 500 (backing services absent here: 503 is an honest answer)."""
    index = http.get("/").json()
    for entry in index["implemented"]:
        assert_no_500(http, entry, {"token": token})
