"""The whole mapping flow as a user runs it (docs/mapping.md), against `zenros launch
deploy/launch/sim.yaml` with the real mapping node, explorer and nav: `/map/start`, drive with
`PUT /system/speed`, `POST /map/current_map_image {"name": "site2"}`, `/map/stop`,
`/navigation/start?map=site2`, a goal reached; and a map explored by the robot itself. The
chassis has a real robot's noise, as the issue's command runs it (`odom_noise:=0.05
range_noise:=0.02`).

The site is one the robot has never seen, generated for the run (tests/worlds.py: a corridor
and two rooms, about 100 m2), at `speed:=3` so that exploring it whole takes a minute or two
(the office, 500 m2 at speed 1, took up to 13 minutes of the suite's critical path;
bench/explore.py explores the office).

"""

from __future__ import annotations

import re
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from worlds import small_world
from zenros.testing import Proc, free_port, store_on_master, unique_prefix, wait_for

ROOT = Path(__file__).resolve().parents[2]
SIM = ROOT / "deploy" / "launch" / "sim.yaml"
READY = 120.0
SPEED = 3  # the world runs this many times faster than the wall clock

pytestmark = [pytest.mark.system, pytest.mark.timeout(900), pytest.mark.xdist_group("sim")]


class Sim:
    def __init__(self, home: Path) -> None:
        self.rest = free_port()
        env = {"ZENROS_HOME": str(home), "ZENROS_PREFIX": unique_prefix(),
               "ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}"}
        ports = {"rest_port": self.rest, "ws_port": free_port(), "modbus_port": free_port(),
                 "rosbridge_port": free_port(), "discovery_port": -1}
        store_on_master(env["ZENROS_HOME"], env["ZENROS_PREFIX"],
                        {f"/gateway/{k}": v for k, v in ports.items()})
        noise = ["odom_noise:=0.05", "range_noise:=0.02"]  # a real robot's (issue 39)
        world = small_world(home / "world")
        self.proc = Proc([sys.executable, "-m", "zenros.cli", "launch", str(SIM), *noise,
                          f"map:={world}", f"speed:={SPEED}"], env=env)
        self.http = httpx.Client(base_url=f"http://127.0.0.1:{self.rest}/api/v1", timeout=30)
        self.token = ""

    def ready(self) -> bool:
        deadline = time.monotonic() + READY
        while time.monotonic() < deadline:
            out = self.proc.output
            started = set(re.findall(r"\[launch\] started (\S+) \(pid", out))
            ready = set(re.findall(r"\[launch\] (\S+) is ready", out))
            if {"gateway", "slam", "nav"} <= started <= ready:
                return True
            if self.proc.popen.poll() is not None:
                return False
            time.sleep(0.5)
        return False

    def get(self, path: str, **params: Any) -> Any:
        r = self.http.get(path, params={**params, "token": self.token})
        return r.json()

    def status(self) -> str:
        return str(self.get("/system/status")["status"])

    def drive(self, speed_x: float, speed_angle: float, seconds: float) -> None:
        """Hold a speed with the dead-man refreshed every 0.1 s (REST teleop)."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.http.put("/system/speed", params={"token": self.token},
                          json={"speed_x": speed_x, "speed_y": 0.0, "speed_angle": speed_angle})
            time.sleep(0.1)

    def close(self) -> None:
        self.http.close()
        self.proc.stop(timeout=30)


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Sim]:
    s = Sim(tmp_path_factory.mktemp("mapping"))
    try:
        assert s.ready(), s.proc.output
        r = s.http.get("/token", params={"username": "admin", "password": "admin"})
        s.token = r.json()["token"]
        yield s
    finally:
        s.close()


def test_build_save_and_navigate_on_a_new_map(sim: Sim) -> None:
    assert wait_for(lambda: sim.get("/map/start").get("result") is True, 60)
    assert wait_for(lambda: sim.status() == "Mapping", 30)
    assert sim.get("/system/galileo_status")["mapStatus"] == 1
    sim.drive(0.3, 0.0, 2.0)  # along the corridor the robot faces (1.8 m in sim time)
    sim.drive(0.0, 0.6, 1.0)
    assert wait_for(lambda: "map_params" in sim.get("/map/current_map_image"), 30)
    # the scans reach the map a few updates behind the drive (later on a loaded host)
    assert wait_for(lambda: sim.get("/system/info")["mapping"]["area_m2"] > 5.0, 30), \
        sim.get("/system/info")["mapping"]
    assert len(sim.get("/map/track")["trajectory"]) > 2
    saved = sim.http.post("/map/current_map_image", params={"token": sim.token},
                          json={"name": "site2"}).json()
    assert saved == {"result": True, "name": "site2"}, saved
    assert "site2" in [m["name"] for m in sim.get("/navigation/saved_maps")]
    assert sim.get("/map/stop")["result"] is True
    assert wait_for(lambda: sim.status() in ("Free", "Navigating"), 30)
    started = sim.get("/navigation/start", map="site2")
    assert started["result"] is True, started
    assert sim.get("/navigation/current_map")["name"] == "site2"
    # the built map's frame is where mapping started: 1 m ahead of it is on the driven path
    task = sim.http.post("/navigation/start_nav_task", params={"token": sim.token},
                         json={"x": 1.0, "y": 0.0, "theta": 0.0}).json()
    assert task.get("state") in ("WORKING", "COMPLETE"), task
    assert wait_for(lambda: sim.get("/task", id=task["id"])["state"] == "COMPLETE", 120)
    pose = sim.get("/navigation/pose")
    assert abs(pose["x"] - 1.0) < 0.25 and abs(pose["y"]) < 0.25, pose


def test_explore_maps_by_itself_and_comes_back(sim: Sim) -> None:
    sim.get("/navigation/stop")
    # the last goal's end reaches GalileoStatus with nav's next status: until then a start
    # is refused as "navigating to a goal"
    assert wait_for(lambda: sim.get("/system/galileo_status")["targetStatus"] != 1, 30)
    started = sim.get("/map/start", mode="explore")
    assert started["result"] is True, started
    assert wait_for(lambda: sim.get("/system/info")["mapping"]["explore"]["state"]
                    in ("done", "failed"), 300)
    explore = sim.get("/system/info")["mapping"]["explore"]
    # the explorer's own outcome, as the gateway shows it: "done", or "failed" with its reason
    # (beside a CPU hog the drive back to the start can fail after the site is mapped:
    # 510 m2 of the office, 53 goals reached, 21 failed in one run); the site is mapped either way
    assert explore["state"] == "done" or explore["message"], explore
    assert explore["explored_area_m2"] > 80.0, explore
    saved = sim.http.post("/map/current_map_image", params={"token": sim.token},
                          json={"name": "explored"}).json()
    assert saved["result"] is True, saved
    assert sim.get("/map/stop")["result"] is True
