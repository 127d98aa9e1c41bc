"""The web dashboard in headless Chromium (Debian's chromium + chromium-driver, via selenium)
against real processes: chassis (10x sim time), nav, tasks and the gateway (REST + rosbridge).

The page must load with no console errors, show the map and the robot, send the robot to a
nav point clicked on the map, pause a task, engage the e-stop, drive from the keyboard and
the teleop pad, and fit a phone-sized window.
Screenshots are saved in
``$ZENROS_ARTIFACTS`` (default ``test-artifacts/`` at the repository root).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from zenros.context import Context
from zenros.msgs.zenros_msgs import NavPoint, SetNavPoints, SetNavPointsRequest
from zenros.msgs.zenros_msgs.tasks import TaskCall, TaskCallRequest
from zenros.rpc import Client
from zenros.testing import Proc, free_port, wait_for

pytestmark = pytest.mark.system

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--window-size=1280,800")
ARTIFACTS = Path(os.environ.get("ZENROS_ARTIFACTS")
                 or Path(__file__).resolve().parents[2] / "test-artifacts")
POINTS = [NavPoint(name="Lab", x=6.0, y=0.0), NavPoint(name="Corridor end", x=20.0, y=0.0)]
TIMEOUT = 30.0

if CHROMIUM is None or CHROMEDRIVER is None:
    pytest.skip("headless Chromium is not installed (apt-get install chromium chromium-driver)",
                allow_module_level=True)

from selenium import webdriver
from selenium.common.exceptions import (
    ElementClickInterceptedException,
    NoSuchElementException,
    StaleElementReferenceException,
)
from selenium.webdriver.chrome.options import Options
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By


class Robot:
    """The processes of a simulated robot with its gateway, on one router."""

    def __init__(self, router: str, prefix: str, home: Path, procs: list[Proc]) -> None:
        self.rest_port = free_port()
        self.rosbridge_port = free_port()
        env = {"ZENROS_HOME": str(home)}
        common = ["-e", router, "--prefix", prefix]

        def start(module: str, *params: str) -> Proc:
            args = [sys.executable, "-m", module, *common]
            for p in params:
                args += ["-p", p]
            proc = Proc(args, env=env)
            procs.append(proc)
            return proc

        chassis = start("zenros.services.chassis", "speed:=10", "publish_clock:=true")
        nav = start("zenros.services.nav", "use_sim_time:=true", f"maps_dir:={home / 'maps'}")
        tasks = start("zenros.services.tasks", "use_sim_time:=true")
        gateway = start("zenros.services.gateway", f"rest_port:={self.rest_port}",
                        f"ws_port:={free_port()}", f"modbus_port:={free_port()}",
                        f"rosbridge_port:={self.rosbridge_port}", "discovery_port:=-1",
                        "no_token_check:=true", f"data_dir:={home / 'gateway'}")
        for proc in (chassis, nav, tasks, gateway):
            assert proc.wait_line("started", TIMEOUT), proc.output


@pytest.fixture
def robot(router: str, prefix: str, tmp_path: Path, procs: list[Proc]) -> Robot:
    return Robot(router, prefix, tmp_path, procs)


@pytest.fixture
def driver(tmp_path: Path) -> Iterator[Any]:
    options = Options()
    options.binary_location = str(CHROMIUM)
    for flag in FLAGS:
        options.add_argument(flag)
    options.add_argument(f"--user-data-dir={tmp_path / 'chromium'}")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    d = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)
    d.set_page_load_timeout(TIMEOUT)
    try:
        yield d
    finally:
        d.quit()


def task_call(ctx: Context, name: str, id: str = "", body: Any = None) -> Any:
    client = Client(ctx, TaskCall, f"/tasks/{name}")
    assert client.wait_for_service(TIMEOUT)
    res = client.call(TaskCallRequest(id=id, body=json.dumps(body) if body else ""), TIMEOUT)
    assert res.success, res.message
    return json.loads(res.body)


def pose(d: Any) -> tuple[float, float] | None:
    """The robot's position as the page shows it."""
    xy = d.execute_script("const e = document.getElementById('pose');"
                          "return e.dataset.x ? [+e.dataset.x, +e.dataset.y] : null;")
    return (float(xy[0]), float(xy[1])) if xy else None


def click_world(d: Any, x: float, y: float) -> None:
    """Click the map canvas where the map point (x, y) is drawn."""
    canvas = d.find_element(By.ID, "map")
    sx, sy = d.execute_script(
        "const p = window.dashboard.view.worldToScreen(arguments[0], arguments[1]);"
        "return [p.x, p.y];", x, y)
    rect = d.execute_script("const r = arguments[0].getBoundingClientRect();"
                            "return [r.width, r.height];", canvas)
    ActionChains(d).move_to_element_with_offset(
        canvas, round(sx - rect[0] / 2), round(sy - rect[1] / 2)).click().perform()


def task_state(d: Any, task_id: str) -> str | None:
    state: str | None = d.execute_script(
        "const li = document.querySelector(`#tasks li[data-id=\"${arguments[0]}\"]`);"
        "return li ? li.dataset.state : null;", task_id)
    return state


def click(d: Any, selector: str) -> None:
    """Click an element, looking it up again if the page re-rendered it meanwhile."""
    def attempt() -> bool:
        try:
            d.find_element(By.CSS_SELECTOR, selector).click()
        except (StaleElementReferenceException, NoSuchElementException,
                ElementClickInterceptedException):
            return False
        return True

    assert wait_for(attempt, TIMEOUT), f"cannot click {selector}"


def still(d: Any, seconds: float) -> bool:
    """True if the robot on the page moved less than 5 cm over ``seconds`` (wall time)."""
    start = pose(d)
    wait_for(lambda: False, seconds)
    end = pose(d)
    return start is not None and end is not None and math.dist(start, end) < 0.05


def test_dashboard_drives_the_robot(robot: Robot, observer: Context, driver: Any) -> None:
    nav_points = Client(observer, SetNavPoints, "/set_nav_points")
    assert nav_points.wait_for_service(TIMEOUT)
    res = nav_points.call(SetNavPointsRequest(path_name="tour", points=POINTS), TIMEOUT)
    assert [p.name for p in res.points] == ["Lab", "Corridor end"]
    task = task_call(observer, "create", body={"name": "corridor and back", "sub_tasks": [
        {"type": "nav_action", "x": 20.0, "y": 0.0, "theta": 0.0},
        {"type": "nav_action", "x": 6.0, "y": 0.0, "theta": 0.0}]})

    # the page loads, with the map, the robot, the nav points and the task
    driver.get(f"http://127.0.0.1:{robot.rest_port}/")
    assert wait_for(lambda: driver.find_element(By.ID, "map")
                    .get_attribute("data-map-loaded") == "1", TIMEOUT)
    assert wait_for(lambda: pose(driver) is not None, TIMEOUT)
    assert wait_for(lambda: len(driver.find_elements(By.CSS_SELECTOR, "#points li")) == 2,
                    TIMEOUT)
    assert wait_for(lambda: task_state(driver, task["id"]) == "WAITTING", TIMEOUT)
    assert "live" in driver.find_element(By.ID, "link-text").text
    start = pose(driver)
    assert start is not None and math.dist(start, (0.0, 0.0)) < 0.5

    # clicking the "Lab" pin sends the robot there
    click_world(driver, POINTS[0].x, POINTS[0].y)
    assert wait_for(lambda: "Lab" in driver.find_element(By.ID, "goal-text").text, TIMEOUT)
    assert wait_for(lambda: math.dist(pose(driver) or start, (6.0, 0.0)) < 0.3, TIMEOUT)

    # start the task from the page, then pause it: the robot stops
    assert wait_for(lambda: driver.find_element(By.ID, "goal-text").text == "", TIMEOUT)
    click(driver, f'#tasks li[data-id="{task["id"]}"] button[data-call="start"]')
    assert wait_for(lambda: task_state(driver, task["id"]) == "WORKING", TIMEOUT)
    here = pose(driver)
    assert wait_for(lambda: math.dist(pose(driver) or here, here) > 0.5, TIMEOUT)
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    assert driver.save_screenshot(str(ARTIFACTS / "dashboard-navigating.png"))
    click(driver, f'#tasks li[data-id="{task["id"]}"] button[data-call="pause"]')
    assert wait_for(lambda: task_state(driver, task["id"]) == "PAUSED", TIMEOUT)
    assert wait_for(lambda: still(driver, 0.5), TIMEOUT)

    # the e-stop: engaged from the page, a goal does not move the robot; released again
    click(driver, "#estop")
    assert wait_for(lambda: driver.find_element(By.ID, "estop")
                    .get_attribute("data-engaged") == "1", TIMEOUT)
    assert driver.find_element(By.ID, "banner").is_displayed()
    click_world(driver, POINTS[0].x, POINTS[0].y)
    assert still(driver, 1.0)
    assert driver.save_screenshot(str(ARTIFACTS / "dashboard-estop.png"))
    click(driver, "#estop")
    assert wait_for(lambda: driver.find_element(By.ID, "estop")
                    .get_attribute("data-engaged") == "0", TIMEOUT)

    # teleop: with navigation stopped, holding W drives the robot, the pad too
    click(driver, "#cancel-goal")
    assert wait_for(lambda: driver.find_element(By.ID, "goal-text").text == "", TIMEOUT)
    assert wait_for(lambda: still(driver, 0.5), TIMEOUT)
    here = pose(driver)
    body = driver.find_element(By.TAG_NAME, "body")
    ActionChains(driver).key_down("w", body).perform()
    try:
        assert wait_for(lambda: math.dist(pose(driver) or here, here) > 0.3, TIMEOUT)
    finally:
        ActionChains(driver).key_up("w", body).perform()
    assert wait_for(lambda: still(driver, 0.5), TIMEOUT)
    here = pose(driver)
    pad = driver.find_element(By.ID, "pad")
    chain = ActionChains(driver).click_and_hold(pad).move_by_offset(0, -40)
    chain.perform()
    try:
        assert wait_for(lambda: math.dist(pose(driver) or here, here) > 0.3, TIMEOUT)
    finally:
        ActionChains(driver).release().perform()
    assert wait_for(lambda: still(driver, 0.5), TIMEOUT)

    # phone-sized: one column, nothing wider than the screen, the map still drawn
    driver.set_window_size(390, 844)
    assert wait_for(lambda: driver.execute_script(
        "const c = document.getElementById('map').getBoundingClientRect();"
        "return document.documentElement.scrollWidth <= window.innerWidth"
        " && c.width > 300 && c.height > 300;"), TIMEOUT)
    assert driver.save_screenshot(str(ARTIFACTS / "dashboard-phone.png"))

    errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
    assert not errors, errors
