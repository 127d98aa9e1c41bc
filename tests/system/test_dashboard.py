"""The web dashboard in headless Chromium (Debian's chromium + chromium-driver, via selenium)
against real processes: chassis (10x sim time), nav, tasks and the gateway (REST + rosbridge).

One robot and one browser serve the module; each test is one step of a session at the page
and starts from a robot standing still with no goal.

The page must load with no console errors, show the map and the robot, send the robot to a
nav point clicked on the map, pause a task, engage the e-stop, drive from the keyboard and
the teleop pad, build a map (start, drive with the pad, watch it grow with the track, save,
stop, explore at a click: against a mapping node that follows the zenros_msgs.slam contract,
tests/integration/slam_stand_in.py, until the real one is launched), and fit a phone-sized
window.
Screenshots are saved in
``$ZENROS_ARTIFACTS`` (default ``test-artifacts/`` at the repository root).
"""

from __future__ import annotations

import math
import os
import re
import shutil
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from zenros.context import Context
from zenros.msgs.zenros_msgs import (
    ListMaps,
    ListMapsRequest,
    NavPoint,
    ResultCode,
    SetNavPoints,
    SetNavPointsRequest,
)
from zenros.msgs.zenros_msgs.tasks import TASK_SERVICES, response_data, task_request
from zenros.rpc import Client
from zenros.session import SessionOptions
from zenros.testing import Proc, free_port, unique_prefix, wait_for

# The module's first test also pays for starting five processes and Chromium, which takes up
# to a minute on a loaded 2-core machine: more than the suite's 60 s per test.
pytestmark = [pytest.mark.system, pytest.mark.timeout(180), pytest.mark.xdist_group("sim")]

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--window-size=1280,800")
ARTIFACTS = Path(os.environ.get("ZENROS_ARTIFACTS")
                 or Path(__file__).resolve().parents[2] / "test-artifacts")
POINTS = [NavPoint(name="Lab", x=6.0, y=0.0), NavPoint(name="Corridor end", x=20.0, y=0.0)]
TIMEOUT = 30.0
SLAM_STAND_IN = Path(__file__).resolve().parents[1] / "integration" / "slam_stand_in.py"

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
from selenium.webdriver.support.ui import Select


class Rig:
    """Router, chassis, nav, tasks and gateway processes, a session of the test's own, and
    a browser on the dashboard."""

    def __init__(self, home: Path) -> None:
        self.procs: list[Proc] = []
        self.rest_port = free_port()
        endpoint = f"tcp/127.0.0.1:{free_port()}"
        prefix = unique_prefix()
        router = self._start([sys.executable, "-m", "zenros.router", "-l", endpoint], {})
        assert router.wait_line("router listening", TIMEOUT), router.output
        env = {"ZENROS_HOME": str(home)}
        common = ["-e", endpoint, "--prefix", prefix]

        def start(module: str, *params: str) -> Proc:
            args = [sys.executable, "-m", module, *common]
            for p in params:
                args += ["-p", p]
            return self._start(args, env)

        started = [
            start("zenros.services.chassis", "speed:=10", "publish_clock:=true"),
            start("zenros.services.nav", "use_sim_time:=true", f"maps_dir:={home / 'maps'}"),
            start("zenros.services.tasks", "use_sim_time:=true"),
            self._start([sys.executable, str(SLAM_STAND_IN), *common], env),
            start("zenros.services.gateway", f"rest_port:={self.rest_port}",
                  f"ws_port:={free_port()}", f"modbus_port:={free_port()}",
                  f"rosbridge_port:={free_port()}", "discovery_port:=-1",
                  "no_token_check:=true", f"data_dir:={home / 'gateway'}"),
        ]
        for proc in started:
            assert proc.wait_line("started", TIMEOUT), proc.output
        self.ctx = Context(SessionOptions(connect=[endpoint]), prefix=prefix)
        self.driver: Any = None

    def _start(self, argv: list[str], env: dict[str, str]) -> Proc:
        proc = Proc(argv, env=env)
        self.procs.append(proc)
        return proc

    def open_browser(self, profile: Path) -> Any:
        options = Options()
        options.binary_location = str(CHROMIUM)
        for flag in FLAGS:
            options.add_argument(flag)
        options.add_argument(f"--user-data-dir={profile}")
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        self.driver = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)
        self.driver.set_page_load_timeout(TIMEOUT)
        return self.driver

    def close(self) -> None:
        if self.driver is not None:
            self.driver.quit()
        if hasattr(self, "ctx"):
            self.ctx.close()
        for proc in reversed(self.procs):
            proc.stop()


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    home = tmp_path_factory.mktemp("dashboard")
    r = Rig(home)
    try:
        nav_points = Client(r.ctx, SetNavPoints, "/set_nav_points")
        assert nav_points.wait_for_service(TIMEOUT)
        res = nav_points.call(SetNavPointsRequest(path_name="tour", points=POINTS), TIMEOUT)
        assert [p.name for p in res.points] == ["Lab", "Corridor end"]
        legs = [{"type": "nav_action", "x": x, "y": 0.0, "theta": 0.0} for x in (20.0, 6.0)]
        # A looping patrol runs until the page stops it: a loaded machine (slow page, slow
        # clicks) cannot let it complete before the pause lands.
        r.task = task_call(r.ctx, "create", body={"name": "corridor patrol", "sub_tasks": legs,
                                                  "loop_flag": True})
        driver = r.open_browser(home / "chromium")
        driver.get(f"http://127.0.0.1:{r.rest_port}/")
        yield r
    finally:
        r.close()


@pytest.fixture
def page(rig: Rig) -> Any:
    """The browser, with the robot standing still, no goal from the page, the e-stop off."""
    d = rig.driver
    assert wait_for(lambda: pose(d) is not None, TIMEOUT)
    if d.find_element(By.ID, "estop").get_attribute("data-engaged") == "1":
        click(d, "#estop")
        assert wait_for(lambda: d.find_element(By.ID, "estop")
                        .get_attribute("data-engaged") == "0", TIMEOUT)
    if d.find_element(By.ID, "goal-text").text:
        click(d, "#cancel-goal")
        assert wait_for(lambda: d.find_element(By.ID, "goal-text").text == "", TIMEOUT)
    assert wait_for(lambda: still(d, 0.3), TIMEOUT)
    return d


def task_call(ctx: Context, name: str, id: str = "", body: Any = None) -> Any:
    client = Client(ctx, TASK_SERVICES[name], f"/tasks/{name}")
    assert client.wait_for_service(TIMEOUT)
    res = client.call(task_request(name, id, body), TIMEOUT)
    assert res.code == ResultCode.OK, res.message
    return response_data(res, single=bool(id))


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

    assert wait_for(attempt, TIMEOUT), (
        f"cannot click {selector}; tasks: "
        + d.execute_script("return document.getElementById('tasks').innerText;"))


def still(d: Any, seconds: float) -> bool:
    """True if the robot on the page moved less than 5 cm over ``seconds`` (wall time)."""
    start = pose(d)
    wait_for(lambda: False, seconds)
    end = pose(d)
    return start is not None and end is not None and math.dist(start, end) < 0.05


def test_the_page_shows_map_robot_points_and_tasks(rig: Rig, page: Any) -> None:
    assert wait_for(lambda: page.find_element(By.ID, "map")
                    .get_attribute("data-map-loaded") == "1", TIMEOUT)
    assert wait_for(lambda: len(page.find_elements(By.CSS_SELECTOR, "#points li")) == 2,
                    TIMEOUT)
    assert wait_for(lambda: task_state(page, rig.task["id"]) == "WAITTING", TIMEOUT)
    assert "live" in page.find_element(By.ID, "link-text").text
    start = pose(page)
    assert start is not None and math.dist(start, (0.0, 0.0)) < 0.5
    # the camera card shows the picked camera's JPEG frames (the browser decodes them)
    front_src = ""

    def shows(which: str) -> bool:
        nonlocal front_src
        loaded = page.execute_script(
            "const i = document.getElementById('camera');"
            "return i.complete && i.naturalWidth === 640 ? i.src : '';")
        if loaded and which == "front":
            front_src = loaded
        return bool(loaded) and (which == "front" or loaded != front_src)

    camera = Select(page.find_element(By.ID, "camera-select"))
    assert camera.first_selected_option.get_attribute("value") == ""  # off until picked
    camera.select_by_value("multi/front")
    assert wait_for(lambda: shows("front"), TIMEOUT)
    camera.select_by_value("multi/back")
    assert wait_for(lambda: shows("back"), TIMEOUT)
    camera.select_by_value("")  # off again: the other tests' robot renders nothing for us
    assert wait_for(lambda: not page.find_element(By.ID, "camera-empty").get_attribute(
        "hidden"), TIMEOUT)


def test_clicking_a_nav_point_sends_the_robot_there(page: Any) -> None:
    here = pose(page)
    assert here is not None
    lab = (POINTS[0].x, POINTS[0].y)
    click_world(page, *lab)
    assert wait_for(lambda: "Lab" in page.find_element(By.ID, "goal-text").text, TIMEOUT)
    assert wait_for(lambda: math.dist(pose(page) or here, lab) < math.dist(here, lab) - 1.0,
                    TIMEOUT)


def test_a_task_started_from_the_page_pauses(rig: Rig, page: Any) -> None:
    task = f'#tasks li[data-id="{rig.task["id"]}"]'
    click(page, f'{task} button[data-call="start"]')
    assert wait_for(lambda: task_state(page, rig.task["id"]) == "WORKING", TIMEOUT)
    here = pose(page)
    assert here is not None
    assert wait_for(lambda: math.dist(pose(page) or here, here) > 0.5, TIMEOUT)
    click(page, f'{task} button[data-call="pause"]')
    assert wait_for(lambda: task_state(page, rig.task["id"]) == "PAUSED", TIMEOUT)
    assert wait_for(lambda: still(page, 0.5), TIMEOUT)
    click(page, f'{task} button[data-call="stop"]')
    assert wait_for(lambda: task_state(page, rig.task["id"]) == "CANCELLED", TIMEOUT)


def test_the_e_stop_holds_the_robot(page: Any) -> None:
    here = pose(page)
    assert here is not None
    far = max(POINTS, key=lambda p: math.dist(here, (p.x, p.y)))  # a goal that takes a while
    click_world(page, far.x, far.y)
    assert wait_for(lambda: far.name in page.find_element(By.ID, "goal-text").text, TIMEOUT)
    assert wait_for(lambda: math.dist(pose(page) or here, here) > 0.3, TIMEOUT)
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    assert page.save_screenshot(str(ARTIFACTS / "dashboard-navigating.png"))
    click(page, "#estop")
    assert wait_for(lambda: page.find_element(By.ID, "estop")
                    .get_attribute("data-engaged") == "1", TIMEOUT)
    assert page.find_element(By.ID, "banner").is_displayed()
    assert wait_for(lambda: still(page, 0.5), TIMEOUT)  # halted mid-run
    now = pose(page) or here
    other = max(POINTS, key=lambda p: math.dist(now, (p.x, p.y)))
    click_world(page, other.x, other.y)  # a new goal does not move it either
    assert wait_for(lambda: other.name in page.find_element(By.ID, "goal-text").text, TIMEOUT)
    assert still(page, 1.0)
    assert page.save_screenshot(str(ARTIFACTS / "dashboard-estop.png"))
    click(page, "#estop")
    assert wait_for(lambda: page.find_element(By.ID, "estop")
                    .get_attribute("data-engaged") == "0", TIMEOUT)


def yaw(d: Any) -> float | None:
    """The robot's heading as the page shows it."""
    value = d.execute_script("return document.getElementById('pose').dataset.yaw || null;")
    return float(value) if value is not None else None


def turned(d: Any, start: float, angle: float) -> bool:
    now = yaw(d)
    return now is not None and abs(math.remainder(now - start, 2 * math.pi)) > angle


def test_teleop_from_the_keyboard(page: Any) -> None:
    start = yaw(page)  # turning in place: no wall can be in the way
    assert start is not None
    body = page.find_element(By.TAG_NAME, "body")
    ActionChains(page).key_down("a", body).perform()
    try:
        assert wait_for(lambda: turned(page, start, 0.3), TIMEOUT)
    finally:
        ActionChains(page).key_up("a", body).perform()


def test_teleop_from_the_pad(page: Any) -> None:
    start = yaw(page)
    assert start is not None
    ActionChains(page).click_and_hold(page.find_element(By.ID, "pad")) \
        .move_by_offset(-40, 0).perform()  # stick to the left: turn left
    try:
        assert wait_for(lambda: turned(page, start, 0.3), TIMEOUT)
    finally:
        ActionChains(page).release().perform()


def mapping_state(d: Any) -> str:
    return str(d.find_element(By.ID, "mapping-state").get_attribute("data-state") or "")


def known_area(d: Any) -> float:
    text = d.find_element(By.ID, "mapping-detail").text
    found = re.search(r"([0-9.]+) m² known", text)
    return float(found.group(1)) if found else 0.0


def test_mapping_from_the_page(rig: Rig, page: Any) -> None:
    """Start mapping, drive with the pad while the map grows with the track, save it under
    a name (it is then a stored map), stop; then explore at a click until it is done."""
    click(page, "#mapping-start")
    assert wait_for(lambda: mapping_state(page) == "mapping", TIMEOUT)
    assert wait_for(lambda: known_area(page) > 0, TIMEOUT)
    first, here = known_area(page), pose(page)
    assert here is not None
    ActionChains(page).click_and_hold(page.find_element(By.ID, "pad")) \
        .move_by_offset(0, -40).perform()  # stick up: drive ahead
    try:
        assert wait_for(lambda: math.dist(pose(page) or here, here) > 0.6, TIMEOUT)
    finally:
        ActionChains(page).release().perform()
    assert wait_for(lambda: known_area(page) > first, TIMEOUT)
    assert wait_for(lambda: page.execute_script(
        "return window.dashboard.view.track.length") >= 2, TIMEOUT)
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    assert page.save_screenshot(str(ARTIFACTS / "dashboard-mapping.png"))
    page.find_element(By.ID, "mapping-name").send_keys("site2")
    click(page, "#mapping-save")
    assert wait_for(lambda: page.find_element(By.ID, "mapping-detail")
                    .get_attribute("data-saved") == "site2", TIMEOUT)
    maps = Client(rig.ctx, ListMaps, "/map_server/list_maps")
    assert maps.wait_for_service(TIMEOUT)
    assert "site2" in [m.name for m in maps.call(ListMapsRequest(), TIMEOUT).maps]
    click(page, "#mapping-stop")
    assert wait_for(lambda: mapping_state(page) == "idle", TIMEOUT)
    click(page, "#mapping-explore")
    assert wait_for(lambda: page.find_element(By.ID, "mapping-detail")
                    .get_attribute("data-explore") == "done", TIMEOUT)
    click(page, "#mapping-stop")
    assert wait_for(lambda: mapping_state(page) == "idle", TIMEOUT)


def test_phone_sized_and_no_console_errors(page: Any) -> None:
    page.set_window_size(390, 844)
    try:
        assert wait_for(lambda: page.execute_script(
            "const c = document.getElementById('map').getBoundingClientRect();"
            "return document.documentElement.scrollWidth <= window.innerWidth"
            " && c.width > 300 && c.height > 300;"), TIMEOUT)
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        assert page.save_screenshot(str(ARTIFACTS / "dashboard-phone.png"))
    finally:
        page.set_window_size(1280, 800)
    errors = [e for e in page.get_log("browser") if e["level"] == "SEVERE"]
    assert not errors, errors


def test_the_ptz_cameras_mjpeg_stream_plays_in_the_browser(rig: Rig) -> None:
    """docs/robot-api.md §17: the URL `onvif_camera/stream` answers is an MJPEG stream a
    browser's <img> shows (the chassis's PTZ camera, on by default)."""
    d = rig.driver
    home = d.current_window_handle
    api = f"http://127.0.0.1:{rig.rest_port}/api/v1"
    stream = httpx.get(f"{api}/system/onvif_camera/stream", timeout=TIMEOUT)
    assert stream.status_code == 200, stream.text
    url = stream.json()["stream"]
    assert url.startswith(f"http://127.0.0.1:{rig.rest_port}/api/v1/system/onvif_camera/mjpeg")
    d.switch_to.new_window("tab")
    try:
        # a page of the gateway's own (about:blank's null origin may not reach loopback), the
        # <img> put in by script (a page with a stream in it never ends loading)
        d.get(f"{api}/")
        d.execute_script("const i = document.createElement('img'); i.id = 'ptz';"
                         "i.src = arguments[0]; document.body.appendChild(i);", url)
        assert wait_for(lambda: d.execute_script(
            "return document.getElementById('ptz').naturalWidth") == 640, TIMEOUT)
        assert d.execute_script("return document.getElementById('ptz').naturalHeight") == 480
    finally:
        d.close()
        d.switch_to.window(home)
