"""`zenros launch` links its peers by configured endpoints (docs/launch.md, "Endpoints"):
each zenros node listens on a loopback port of its own, kept across respawns, and connects to
the router and to every node started before it; clients, nodes with a Zenoh config file or
their own endpoints, and other programs are left as they are."""

from __future__ import annotations

import asyncio

import pytest
from zenros.launch.model import ProcessSpec
from zenros.launch.zenoh_hooks import ZenohLaunch

ROUTER = "tcp/127.0.0.1:17447"


def start(launch: ZenohLaunch, spec: ProcessSpec) -> dict[str, str]:
    return dict(asyncio.run(launch.before_start(spec)).env)


@pytest.fixture(autouse=True)
def _no_caller_endpoints(monkeypatch: pytest.MonkeyPatch) -> None:
    for key in ("ZENROS_CONNECT", "ZENROS_LISTEN", "ZENROS_MODE", "ZENROS_CONFIG"):
        monkeypatch.delenv(key, raising=False)


def node(name: str, namespace: str = "/", **env: str) -> ProcessSpec:
    return ProcessSpec(name, ("python", "-m", f"zenros.services.{name}"), namespace,
                       ros_args=True, env=env)


def test_each_node_listens_on_its_own_port_and_connects_to_the_ones_before() -> None:
    launch = ZenohLaunch(ROUTER)
    a = start(launch, node("chassis", "/robot1"))
    b = start(launch, node("chassis", "/robot2"))
    c = start(launch, node("gateway"))
    listens = [e["ZENROS_LISTEN"] for e in (a, b, c)]
    assert len(set(listens)) == 3 and all(x.startswith("tcp/127.0.0.1:") for x in listens)
    assert a["ZENROS_CONNECT"] == ROUTER
    assert b["ZENROS_CONNECT"] == f"{ROUTER},{listens[0]}"
    assert c["ZENROS_CONNECT"] == f"{ROUTER},{listens[0]},{listens[1]}"
    # a respawn keeps its port and links to every other node
    again = start(launch, node("chassis", "/robot1"))
    assert again["ZENROS_LISTEN"] == listens[0]
    assert again["ZENROS_CONNECT"] == f"{ROUTER},{listens[1]},{listens[2]}"


def test_the_callers_router_endpoints_come_first(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ZENROS_CONNECT", "tcp/127.0.0.1:27447,tcp/127.0.0.1:27448")
    launch = ZenohLaunch()
    first = start(launch, node("master"))
    second = start(launch, node("nav"))
    assert first["ZENROS_CONNECT"] == "tcp/127.0.0.1:27447,tcp/127.0.0.1:27448"
    assert second["ZENROS_CONNECT"] == (
        f"tcp/127.0.0.1:27447,tcp/127.0.0.1:27448,{first['ZENROS_LISTEN']}")


@pytest.mark.parametrize("env", [{"ZENROS_MODE": "client"}, {"ZENROS_CONFIG": "peer.json5"},
                                 {"ZENROS_LISTEN": "tcp/127.0.0.1:5000"},
                                 {"ZENROS_CONNECT": "tcp/127.0.0.1:6000"}])
def test_a_node_with_its_own_mode_config_or_endpoints_is_left_alone(env: dict[str, str]
                                                                     ) -> None:
    launch = ZenohLaunch(ROUTER)
    start(launch, node("master"))
    out = start(launch, node("schedule", **env))
    assert "ZENROS_LISTEN" not in out or out["ZENROS_LISTEN"] == env.get("ZENROS_LISTEN")
    assert out.get("ZENROS_CONNECT") in (ROUTER, env.get("ZENROS_CONNECT"))


def test_a_config_file_from_the_caller_turns_it_off(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ZENROS_CONFIG", "deploy/demo/zenoh-host.json5")
    out = start(ZenohLaunch(ROUTER), node("nav"))
    assert "ZENROS_LISTEN" not in out and out["ZENROS_CONNECT"] == ROUTER


def test_other_programs_get_only_the_router() -> None:
    launch = ZenohLaunch(ROUTER)
    out = start(launch, ProcessSpec("sh", ("sh", "-c", "true")))
    assert out == {"ZENROS_CONNECT": ROUTER}
