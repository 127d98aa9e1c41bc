"""docs/robot-api.md §3.3's restart_robot and shutdown without a launch to act on: a 503
naming the missing service and how to get one, never a fake success (with a launch:
tests/system/test_launch_control.py); the operator's host commands (wifi, is_online,
restart_router, restart_novnc) run as configured, with the request's values as plain
arguments."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import httpx
import pytest
from zenros.context import Context
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway


def test_without_a_launch_the_host_operations_are_503(gw: GatewayNode,
                                                       http: httpx.Client) -> None:
    for path, what in (("/system/restart_robot", "restart"), ("/system/shutdown", "shut down")):
        r = http.get(path)
        body = r.json()
        assert r.status_code == 503, r.text
        assert body["description"].startswith(f"no launch to {what}: /launch/"), body
        assert "zenros launch" in body["description"], body
    assert http.get("/system/restart_robot", params={"now": 1}).status_code == 400


def test_the_operators_host_commands(ctx_pair: list[Context], tmp_path: Path) -> None:
    """§3.5's wifi and is_online and §3.3's restart_router run the commands of the
    configuration file, each request value one argument (a shell's metacharacters stay
    text); one not configured is a 503 saying where to give it; a failing one a 502."""
    out = tmp_path / "argv.json"
    record = [sys.executable, "-c",
              f"import json, sys; open({str(out)!r}, 'w').write(json.dumps(sys.argv[1:]))"]
    config = {"host_commands": {
        "wifi": [*record, "connect", "{ssid}", "password", "{password}"],
        "is_online": ["false"],
        "restart_router": ["sh", "-c", "echo router {ip} refused >&2; exit 3"]}}
    (tmp_path / "config.json").write_text(json.dumps(config))
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=30) as http:
        r = http.get("/system/wifi", params={"ssid": "Lab; rm -rf ~", "password": "p$(x) 'q'"})
        assert r.status_code == 200 and r.json() == {"status": "ok"}, r.text
        assert json.loads(out.read_text()) == ["connect", "Lab; rm -rf ~", "password",
                                               "p$(x) 'q'"]
        assert http.get("/system/is_online").json() == {"result": False}
        r = http.get("/system/restart_router", params={"type": "tplink", "ip": "10.0.0.1"})
        assert r.status_code == 502, r.text
        assert r.json()["description"] == ("the restart_router command failed (exit code 3): "
                                           "router 10.0.0.1 refused"), r.text
        r = http.get("/system/restart_novnc")
        assert r.status_code == 503 and "host_commands.restart_novnc" in \
            r.json()["description"], r.text
        for params, words in (({"ssid": "bad\x01"}, "ssid"), ({"ssid": "x" * 33}, "ssid"),
                              ({"ssid": "a", "password": "é"}, "password")):
            r = http.get("/system/wifi", params=params)
            assert r.status_code == 400 and words in r.json()["description"], r.text
        r = http.get("/system/restart_router", params={"type": "tplink", "ip": "a.b"})
        assert r.status_code == 400 and "not an IP address" in r.json()["description"]


def test_an_unknown_host_command_stops_the_gateway_at_start(ctx_pair: list[Context],
                                                            tmp_path: Path) -> None:
    from zenros.errors import ConfigError

    (tmp_path / "config.json").write_text(json.dumps({"host_commands": {"reboot": ["x"]}}))
    with pytest.raises(ConfigError, match="unknown operation"), \
            running_gateway(ctx_pair[0], tmp_path):
        pass
