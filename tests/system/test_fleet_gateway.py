"""`zenros launch fleet.yaml robots:=3` and its one gateway: goals sent through the gateway's
REST API to each robot (each to its own robot's path, robot1's also at the single-robot
path) move each robot to its own goal; an e-stop through the gateway's rosbridge stops that
robot alone; each robot's tasks are its own. The dashboard's fleet view (headless Chromium)
lists every robot, draws the others on the map, e-stops one from its row, drives the one
picked and draws the segments it holds in schedule mode."""

from __future__ import annotations

import math
import os
import shutil
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import pytest
import roslibpy
from zenros.testing import Proc, free_port, unique_prefix, wait_for

pytestmark = [pytest.mark.system, pytest.mark.xdist_group("sim"), pytest.mark.timeout(600)]

ROOT = Path(__file__).resolve().parents[2]
ROBOTS = ("robot1", "robot2", "robot3")
SPACING = 2.5  # fleet.yaml: robot k starts at ((k - 1) * 2.5, 0, 0)
AHEAD = 1.2    # each robot's goal: this far ahead of where it starts
STOPPED = "robot2"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
ARTIFACTS = Path(os.environ.get("ZENROS_ARTIFACTS") or ROOT / "test-artifacts")


@dataclass
class Fleet:
    proc: Proc
    http: httpx.Client
    token: str
    rosbridge_port: int
    started: float  # time.monotonic() of the launch

    def get(self, path: str, **params: Any) -> Any:
        r = self.http.get(path, params={"token": self.token, **params})
        assert r.status_code == 200, (path, r.status_code, r.text)
        return r.json()

    def robots(self) -> dict[str, dict[str, Any]]:
        return {r["name"]: r for r in self.get("/robots")["robots"]}


@pytest.fixture(scope="module")
def fleet(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Fleet]:
    home = tmp_path_factory.mktemp("fleetgw")
    ports = {name: free_port() for name in ("rest_port", "ws_port", "rosbridge_port",
                                            "modbus_port")}
    started = time.monotonic()
    proc = Proc([sys.executable, "-m", "zenros.cli", "launch",
                 str(ROOT / "deploy" / "launch" / "fleet.yaml"), f"robots:={len(ROBOTS)}",
                 f"data:={home}", "passing_width:=3.0",  # the corridor: one traffic segment
                 *(f"{k}:={v}" for k, v in ports.items())],
                env={"ZENROS_HOME": str(home), "ZENROS_PREFIX": unique_prefix(),
                     "ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}"})
    try:
        for name in ROBOTS:
            assert proc.wait_line(f"{name}/robot is ready", 240), proc.output
        assert proc.wait_line("gateway is ready", 120), proc.output
        with httpx.Client(base_url=f"http://127.0.0.1:{ports['rest_port']}/api/v1",
                          timeout=20) as http:
            r = http.get("/token", params={"username": "admin", "password": "admin"})
            assert r.status_code == 200, r.text
            yield Fleet(proc, http, r.json()["token"], ports["rosbridge_port"], started)
    finally:
        proc.stop(timeout=60)


def start_of(name: str) -> float:
    return (int(name.removeprefix("robot")) - 1) * SPACING


def near(robot: dict[str, Any], x: float, tol: float) -> bool:
    pose = robot["pose"]
    return pose is not None and math.hypot(pose["x"] - x, pose["y"]) < tol


def test_the_gateway_serves_every_robot(fleet: Fleet) -> None:
    assert wait_for(lambda: set(fleet.robots()) == set(ROBOTS), 60), fleet.robots()
    listed = fleet.get("/robots")
    assert listed["default"] == "robot1"
    assert wait_for(lambda: all(near(r, start_of(n), 0.1) and r["online"]
                                for n, r in fleet.robots().items()), 60), fleet.robots()
    print(f"\nlaunch to every robot served and localised: "
          f"{time.monotonic() - fleet.started:.1f} s")
    # each robot's own status, and the single-robot paths are robot1's; GalileoStatus is
    # composed at the status rate, so it may be one period behind the list's pose
    for name in ROBOTS:
        def pos_x(name: str = name) -> float:
            return float(fleet.get(f"/robots/{name}/system/galileo_status")["currentPosX"])
        assert wait_for(lambda: abs(pos_x() - start_of(name)) < 0.1, 10), (name, pos_x())
    assert fleet.get("/system/galileo_status")["currentPosX"] == pytest.approx(0.0, abs=0.1)
    r = fleet.http.get("/robots/robot4/system/status", params={"token": fleet.token})
    assert r.status_code == 404 and "no robot 'robot4'" in r.json()["description"]


def test_goals_and_estop_through_the_gateway_reach_their_own_robot(fleet: Fleet) -> None:
    assert wait_for(lambda: all(near(r, start_of(n), 0.1)
                                for n, r in fleet.robots().items()), 60), fleet.robots()
    ros = roslibpy.Ros(host="127.0.0.1", port=fleet.rosbridge_port)
    ros.run(timeout=20)
    try:
        def estop(name: str, on: bool) -> None:
            service = roslibpy.Service(ros, f"/{name}/chassis/set_estop", "std_srvs/SetBool")
            assert service.call(roslibpy.ServiceRequest({"data": on}), timeout=20)["success"]

        estop(STOPPED, True)
        assert wait_for(lambda: {n: r["estop"] for n, r in fleet.robots().items()}
                        == {n: n == STOPPED for n in ROBOTS}, 20), fleet.robots()
        t0 = time.monotonic()
        tasks = {}
        for name in ROBOTS:  # robot1's goal at the single-robot path: it is the default
            path = "" if name == "robot1" else f"/robots/{name}"
            r = fleet.http.post(f"{path}/navigation/start_nav_task", params={
                "token": fleet.token}, json={"x": start_of(name) + AHEAD, "y": 0.0})
            assert r.status_code == 200, (name, r.text)
            tasks[name] = r.json()["id"]
        moving = [n for n in ROBOTS if n != STOPPED]
        assert wait_for(lambda: all(near(fleet.robots()[n], start_of(n) + AHEAD, 0.25)
                                    for n in moving), 120), fleet.robots()
        print(f"\ntwo robots driven {AHEAD} m through the gateway: "
              f"{time.monotonic() - t0:.1f} s")
        assert near(fleet.robots()[STOPPED], start_of(STOPPED), 0.03), fleet.robots()
        # each robot's task is in its own tasks service, and only there
        for name in ROBOTS:
            ids = {t["id"] for t in fleet.get(f"/robots/{name}/task")}
            assert tasks[name] in ids and not ids & {tasks[n] for n in ROBOTS if n != name}
        # released (its held task stopped), the stopped robot drives to a new goal of its own;
        # the others stay where they are
        if fleet.get(f"/robots/{STOPPED}/task", id=tasks[STOPPED])["state"] in (
                "WAITTING", "WORKING", "PAUSED"):
            fleet.get(f"/robots/{STOPPED}/task/stop", id=tasks[STOPPED])
        estop(STOPPED, False)
        r = fleet.http.post(f"/robots/{STOPPED}/navigation/start_nav_task", params={
            "token": fleet.token}, json={"x": start_of(STOPPED) + AHEAD, "y": 0.0})
        assert r.status_code == 200, r.text
        assert wait_for(lambda: near(fleet.robots()[STOPPED], start_of(STOPPED) + AHEAD, 0.25),
                        120), fleet.robots()
        assert all(near(fleet.robots()[n], start_of(n) + AHEAD, 0.25) for n in moving)
    finally:
        ros.close()


@pytest.mark.skipif(CHROMIUM is None or CHROMEDRIVER is None,
                    reason="headless Chromium is not installed (apt-get install chromium "
                           "chromium-driver)")
def test_the_dashboards_fleet_view(fleet: Fleet, tmp_path: Path) -> None:
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By

    options = Options()
    options.binary_location = str(CHROMIUM)
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update",
                 "--window-size=1280,800", f"--user-data-dir={tmp_path / 'chromium'}"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    d: Any = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)
    try:
        d.set_page_load_timeout(30)
        d.get(str(fleet.http.base_url).removesuffix("/api/v1/"))

        def rows() -> dict[str, dict[str, str]]:
            out: dict[str, dict[str, str]] = d.execute_script(
                "const out = {}; for (const li of document.querySelectorAll('#fleet li'))"
                " out[li.dataset.robot] = {...li.dataset, current: "
                "li.classList.contains('current') ? '1' : ''}; return out;")
            return out

        def others() -> list[str]:
            names: list[str] = d.execute_script(
                "return window.dashboard.view.others.map((o) => o.name);")
            return sorted(names)

        # the page shows the card once its config.json answered (a module script, async)
        assert wait_for(lambda: d.find_element(By.ID, "fleet-card").is_displayed(), 30)
        assert wait_for(lambda: set(rows()) == set(ROBOTS) and all(
            r["state"] and r["battery"] for r in rows().values()), 30), rows()
        assert rows()["robot1"]["current"] and not rows()["robot2"]["current"]
        assert wait_for(lambda: others() == ["robot2", "robot3"], 30), others()
        # e-stop robot3 from its row, then release it
        for on in (True, False):
            d.find_element(By.CSS_SELECTOR, '#fleet li[data-robot="robot3"] .estop-small').click()
            want = {n: on and n == "robot3" for n in ROBOTS}
            flag = "1" if on else "0"
            assert wait_for(lambda w=want: {n: r["estop"] for n, r in fleet.robots().items()}
                            == w, 20), fleet.robots()
            assert wait_for(lambda f=flag: rows()["robot3"]["estop"] == f, 20), rows()
        # pick robot2: the page drives robot2 (a goal from the map moves robot2 alone)
        d.find_element(By.CSS_SELECTOR, '#fleet li[data-robot="robot2"] .drive').click()
        assert wait_for(lambda: d.find_element(By.ID, "robot-name").text == "robot2", 30)
        assert wait_for(lambda: rows().get("robot2", {}).get("current") == "1", 30), rows()
        assert wait_for(lambda: others() == ["robot1", "robot3"], 30), others()
        # robot2 drives in schedule mode: the map draws the segments it holds, its row says so
        fleet.get("/robots/robot2/navigation/start_schedule_mode")
        before = fleet.robots()
        x = before["robot2"]["pose"]["x"] + 0.8
        assert wait_for(lambda: d.execute_script(
            "return document.getElementById('pose').dataset.x !== undefined;"), 30)
        d.execute_script("window.dashboard.navigate(arguments[0], 0, 0, null);", x)
        assert wait_for(lambda: near(fleet.robots()["robot2"], x, 0.25), 120), fleet.robots()
        assert d.execute_script("return window.dashboard.fleet.held.has('robot2');")
        fleet.get("/robots/robot2/navigation/stop_schedule_mode")
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        d.save_screenshot(str(ARTIFACTS / "dashboard-fleet.png"))
        after = fleet.robots()
        for name in ("robot1", "robot3"):
            assert near(after[name], before[name]["pose"]["x"], 0.03), (before, after)
        errors = [e for e in d.get_log("browser") if e["level"] == "SEVERE"]
        assert errors == []
    finally:
        d.quit()
