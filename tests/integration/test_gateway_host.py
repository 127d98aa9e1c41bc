"""docs/robot-api.md §3.3's restart_robot and shutdown without a launch to act on: a 503
naming the missing service and how to get one, never a fake success (with a launch:
tests/system/test_launch_control.py); the operator's host commands (wifi, is_online,
restart_router, restart_novnc) run as configured, with the request's values as plain
arguments."""

from __future__ import annotations

import json
import shutil
import ssl
import subprocess
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


def _self_signed(folder: Path, days: int) -> tuple[Path, Path]:
    cert, key = folder / "cert.pem", folder / "key.pem"
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-subj",
                    "/CN=localhost", "-days", str(days), "-keyout", str(key), "-out",
                    str(cert)], check=True, capture_output=True, timeout=60)
    return cert, key


@pytest.mark.skipif(shutil.which("openssl") is None, reason="needs the openssl program")
def test_https_and_check_cert(ctx_pair: list[Context], tmp_path: Path) -> None:
    """With tls_cert and tls_key the REST API is HTTPS (an outside client verifies it against
    the certificate), and /system/check_cert reads that certificate from its file."""
    cert, key = _self_signed(tmp_path, 30)
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True, tls_cert=str(cert),
                         tls_key=str(key)) as gw:
        base = f"https://localhost:{gw.rest_port}/api/v1"
        trust = ssl.create_default_context(cafile=str(cert))
        with httpx.Client(base_url=base, verify=trust, timeout=15) as https:
            got = https.get("/system/check_cert").json()
        assert got["status"] == "ok" and got["subject"] == "commonName=localhost", got
        assert got["days_left"] in (29, 30) and got["not_after"].endswith("Z"), got
        with pytest.raises(httpx.HTTPError):  # plain HTTP is not served on that port
            httpx.get(f"http://127.0.0.1:{gw.rest_port}/api/v1/system/check_cert", timeout=5)
        cert.write_text("not a certificate")  # read again on every check
        with httpx.Client(base_url=base, verify=False, timeout=15) as https:
            r = https.get("/system/check_cert")
        assert r.status_code == 502 and "cannot be read" in r.json()["description"], r.text


def test_check_cert_without_tls_and_bad_tls_parameters(ctx_pair: list[Context],
                                                       tmp_path: Path) -> None:
    from zenros.errors import ConfigError

    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1", timeout=15) as http:
        r = http.get("/system/check_cert")
        assert r.status_code == 503 and "tls_cert" in r.json()["description"], r.text
    (tmp_path / "junk.pem").write_text("junk")
    for params, words in (({"tls_cert": str(tmp_path / "junk.pem")}, "both"),
                          ({"tls_cert": str(tmp_path / "junk.pem"),
                            "tls_key": str(tmp_path / "junk.pem")}, "junk.pem")):
        with pytest.raises(ConfigError, match=words), \
                running_gateway(ctx_pair[0], tmp_path / "bad", **params):
            pass
