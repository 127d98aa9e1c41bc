"""A goal two floors up, as a user sends it (docs/building.md): `zenros launch
deploy/launch/building.yaml speed:=10` (the demo tower: three floors, one lift, its
controller), then `POST /navigation/start_nav_task {"x": 10, "y": 0, "map": "floor3"}`. The
robot drives to the lift's hall point, calls the car, rides it up, is relocalised on floor 3
and drives on to the goal."""

from __future__ import annotations

import math
import re
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from zenros.testing import Proc, free_port, store_on_master, unique_prefix, wait_for

ROOT = Path(__file__).resolve().parents[2]
LAUNCH = ROOT / "deploy" / "launch" / "building.yaml"
READY = 120.0

pytestmark = [pytest.mark.system, pytest.mark.timeout(600), pytest.mark.xdist_group("sim")]


class Tower:
    def __init__(self, home: Path) -> None:
        self.rest = free_port()
        env = {"ZENROS_HOME": str(home), "ZENROS_PREFIX": unique_prefix(),
               "ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}"}
        ports = {"rest_port": self.rest, "ws_port": free_port(), "modbus_port": free_port(),
                 "rosbridge_port": free_port(), "discovery_port": -1}
        store_on_master(env["ZENROS_HOME"], env["ZENROS_PREFIX"],
                        {f"/gateway/{k}": v for k, v in ports.items()})
        self.proc = Proc([sys.executable, "-m", "zenros.cli", "launch", str(LAUNCH),
                          "speed:=10", *(f"{k}:={v}" for k, v in ports.items())], env=env)
        self.http = httpx.Client(base_url=f"http://127.0.0.1:{self.rest}/api/v1", timeout=30)
        self.token = ""

    def ready(self) -> bool:
        deadline = time.monotonic() + READY
        while time.monotonic() < deadline:
            out = self.proc.output
            started = set(re.findall(r"\[launch\] started (\S+) \(pid", out))
            ready = set(re.findall(r"\[launch\] (\S+) is ready", out))
            if {"gateway", "nav", "elevator", "tasks"} <= started <= ready:
                return True
            if self.proc.popen.poll() is not None:
                return False
            time.sleep(0.5)
        return False

    def get(self, path: str, **params: Any) -> Any:
        return self.http.get(path, params={**params, "token": self.token}).json()

    def close(self) -> None:
        self.http.close()
        self.proc.stop(timeout=30)


@pytest.fixture(scope="module")
def tower(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Tower]:
    t = Tower(tmp_path_factory.mktemp("tower"))
    try:
        assert t.ready(), t.proc.output
        t.token = t.http.get("/token", params={"username": "admin",
                                               "password": "admin"}).json()["token"]
        yield t
    finally:
        t.close()


def test_a_goal_two_floors_up(tower: Tower) -> None:
    assert wait_for(lambda: tower.get("/navigation/current_map").get("name") == "floor1", 60)
    links = tower.get("/navigation/point_connections")["connections"]
    assert {c["type"] for c in links} == {"elevator"} and len(links) == 3
    r = tower.http.post("/navigation/start_nav_task", params={"token": tower.token},
                        json={"x": 10.0, "y": 0.0, "theta": 0.0, "map": "floor3"})
    assert r.status_code == 200, r.text
    task = r.json()["id"]
    results: list[str] = []

    def done() -> bool:
        doc = tower.get("/task", id=task)
        for sub in doc.get("sub_tasks", []):
            text = sub.get("result") or ""
            if text and (not results or results[-1] != text):
                results.append(text)
        return doc["state"] in ("COMPLETE", "ERROR", "CANCELLED")

    assert wait_for(done, 300), results
    doc = tower.get("/task", id=task)
    assert doc["state"] == "COMPLETE", (results, tower.proc.output[-3000:])
    for stage in ("waiting for elevator lift1 at level 1", "riding elevator lift1 to level 3",
                  "leaving elevator lift1 at level 3"):
        assert any(stage in t for t in results), results
    assert tower.get("/navigation/current_map")["name"] == "floor3"
    pose = tower.get("/navigation/pose")
    assert math.hypot(pose["x"] - 10.0, pose["y"]) < 0.3, pose
    lift = tower.get("/navigation/get_elevator_info", elevator_name="lift1")
    assert lift["level"] == 3, lift
