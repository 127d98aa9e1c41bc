"""The robot a new user gets: a fresh venv, zenros installed with no extras, the sim launched.

README command 1 is ``python3 -m venv .venv && .venv/bin/pip install -e . && .venv/bin/zenros
launch deploy/launch/sim.yaml``. Each case makes a fresh venv, installs this checkout the way a
user does, editable (``pip install -e`` of a copy of the checkout: a clean clone's files, since
the build writes into its source and the running suite keeps its own) or not (the wheel
``pip install <checkout>`` builds: conftest.py's ``plain_wheel``, shared with test_install.py),
with its dependencies and no extras, then, from that venv only:

- imports every module of zenros outside the checkout (one that needs an optional extra must
  fail naming it), and finds the demo map and the launch files;
- launches the sim (from the checkout by path; or by its bare name ``sim.yaml`` from a folder
  outside it) on free ports, in a private ZENROS_HOME with its own key prefix;
- 30 s after the launch: every process of sim.yaml alive and started once (the supervisor's
  launch.log), and each outside door answering: REST (``/api/v1/token``), the dashboard page,
  the topic WebSocket, the dashboard's socket (rosbridge: a ``call_service /rosapi/topics``),
  Modbus TCP.

The clients (httpx, websockets, pymodbus) are the test venv's, never the fresh one's. The two
cases are prepared and launched side by side (module fixture ``robots``), so their installs
overlap and their 30 s runs are one; each test checks its own case.
"""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import httpx
import pytest
from checkout import clean_copy
from pymodbus.client import ModbusTcpClient
from websockets.sync.client import connect
from zenros.testing import free_port, unique_prefix, wait_for

pytestmark = pytest.mark.system

ROOT = Path(__file__).resolve().parents[2]
RUN_FOR = 30.0  # seconds the sim runs before the checks (the "30 s later")
# The gateway binds port 0 for each (the system's choice, so no race for a "free" port with
# the box's other sockets) and logs the port it got; discovery goes to a socket the test holds.
BOUND = {
    "rest_port": r"REST API on http://127\.0\.0\.1:(\d+)/",
    "ws_port": r"topic WebSocket on ws://127\.0\.0\.1:(\d+)/",
    "modbus_port": r"Modbus TCP on 127\.0\.0\.1:(\d+)",
    "rosbridge_port": r"rosbridge v2 listening on ws://127\.0\.0\.1:(\d+)/",
}

# Run by the fresh venv's python outside the checkout: every module of zenros, imported.
IMPORT_ALL = r"""
import importlib, json, pkgutil, sys
import zenros, zenros.services
names, failed = set(), {}
for pkg in (zenros, zenros.services):
    for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + ".",
                                   onerror=lambda n: failed.setdefault(n, repr(sys.exc_info()[1]))):
        names.add(m.name)
for name in sorted(names):
    if not name.endswith("__main__"):
        try:
            importlib.import_module(name)
        except Exception as exc:
            failed[name] = f"{type(exc).__name__}: {exc}"
from pathlib import Path
from zenros.launch.files import find_launch_file
from zenros.launch.loader import load_launch
from zenros.services.chassis.config import DEMO_MAP as chassis_map
from zenros.services.nav.params import DEMO_MAP as nav_map
sim = find_launch_file("sim.yaml")
maps = [p["map"] for spec in load_launch(sim).processes for p in spec.params
        if isinstance(p, dict) and "map" in p]  # sim.yaml's $(dirname)/../maps/...
print(json.dumps({"zenros": zenros.__file__, "modules": len(names), "failed": failed,
                  "sim": str(sim), "sim_maps": [m for m in maps if Path(m).is_file()],
                  "maps": [str(p) for p in (chassis_map, nav_map) if p.is_file()]}))
"""


@dataclass
class Install:
    venv: Path
    src: Path  # the checkout it was installed from
    env: dict[str, str] = field(default_factory=dict)

    @property
    def bin(self) -> Path:
        return self.venv / "bin"

    def run(self, *argv: str, cwd: Path, timeout: float = 60) -> subprocess.CompletedProcess[str]:
        return subprocess.run(list(argv), cwd=cwd, env=self.env, capture_output=True, text=True,
                              timeout=timeout, check=False)


def _user_env(venv: Path) -> dict[str, str]:
    """The environment of a user's shell: none of the test venv's Python settings."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("PYTHON", "ZENROS_", "PYTEST")) and k != "VIRTUAL_ENV"}
    env["PATH"] = os.pathsep.join(
        p for p in os.environ.get("PATH", "").split(os.pathsep)
        if p and Path(p).resolve() != Path(sys.executable).parent.resolve())
    env["PYTHONUNBUFFERED"] = "1"
    return env


def _install(tmp: Path, wheel: Path | None) -> Install:
    """A fresh venv and, with no extras, ``pip install -e <copy of the checkout>`` (``wheel``
    None) or ``pip install <wheel>``: the wheel ``pip install <checkout>`` builds."""
    src = clean_copy(tmp / "zenros") if wheel is None else ROOT
    venv = tmp / "venv"
    inst = Install(venv, src, _user_env(venv))
    r = inst.run(sys.executable, "-m", "venv", str(venv), cwd=tmp, timeout=300)  # slow box: minutes
    assert r.returncode == 0, r.stderr
    what = ["-e", str(src)] if wheel is None else [str(wheel)]
    r = inst.run(str(inst.bin / "pip"), "install", "-q", *what, cwd=src if wheel is None else tmp,
                 timeout=480)  # two installs side by side
    assert r.returncode == 0, r.stderr[-3000:]
    return inst


def _check_imports(inst: Install, outside: Path, editable: bool) -> None:
    r = inst.run(str(inst.bin / "python"), "-c", IMPORT_ALL, cwd=outside, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    found = json.loads(r.stdout.strip().splitlines()[-1])
    assert found["modules"] > 200, found
    # A module that needs an optional extra says which: `pip install 'zenros[foxglove]'`.
    missing = {k: v for k, v in found["failed"].items() if "zenros[" not in v}
    assert not missing, f"not importable in a plain install: {missing}"
    home = inst.src if editable else inst.venv
    assert found["zenros"].startswith(str(home)), found["zenros"]
    assert found["sim"].startswith(str(home)), found["sim"]
    assert len(found["maps"]) == 2, f"the demo map is missing: {found}"  # services' default
    assert len(found["sim_maps"]) == 2, f"sim.yaml's map is missing: {found}"  # chassis, nav


class Launch:
    """``zenros launch`` of the fresh venv on free ports; stopped by its PIDs in teardown."""

    def __init__(self, inst: Install, file: str, cwd: Path, home: Path) -> None:
        self.home = home
        env = {**inst.env, "ZENROS_HOME": str(home), "ZENROS_PREFIX": unique_prefix(),
               "ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}"}
        r = subprocess.run([str(inst.bin / "zenros"), "launch", file, "--print"], cwd=cwd,
                           env=env, capture_output=True, text=True, timeout=60, check=False)
        assert r.returncode == 0, r.stderr
        self.labels = {line.split(":", 1)[0] for line in r.stdout.splitlines() if ":" in line}
        assert {"master", "chassis", "nav", "tasks", "gateway"} <= self.labels, r.stdout
        self.discovery = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.discovery.bind(("127.0.0.1", 0))
        self.discovery.settimeout(0.5)
        self.ports = {name: 0 for name in BOUND}
        self.ports["discovery_port"] = self.discovery.getsockname()[1]
        argv = [str(inst.bin / "zenros"), "launch", file,
                *(f"{name}:={port}" for name, port in self.ports.items())]
        self.log = home.parent / "launch-output.txt"
        self.started = time.monotonic()
        with self.log.open("wb") as out:
            self.proc = subprocess.Popen(argv, cwd=cwd, env=env, stdout=out,
                                         stderr=subprocess.STDOUT, start_new_session=True)

    @property
    def output(self) -> str:
        return self.log.read_text(errors="replace")

    def ready(self) -> bool:
        out = self.output
        return self.labels <= set(re.findall(r"\[launch\] (\S+) is ready", out))

    def bound(self) -> dict[str, int]:
        """The ports the gateway listens on, from its log (its latest start)."""
        text = (self.home / "logs" / "latest" / "gateway.log").read_text(errors="replace")
        found = {name: re.findall(pattern, text) for name, pattern in BOUND.items()}
        return {name: int(ports[-1]) for name, ports in found.items() if ports}

    def pids(self) -> dict[str, list[int]]:
        """Each process's PIDs, one per start, from the supervisor's launch.log."""
        found: dict[str, list[int]] = {}
        logs = sorted((self.home / "logs").glob("*/launch.log"))
        text = logs[-1].read_text(errors="replace") if logs else ""
        for label, pid in re.findall(r"\] started (\S+) \(pid (\d+)\)", text):
            found.setdefault(label, []).append(int(pid))
        return found

    def stop(self) -> None:
        """SIGINT to the launch (it stops its processes and router), then SIGKILL to what is
        left: the launch's group, each process's own group, the router."""
        pids = [p for ps in self.pids().values() for p in ps]
        pids += [int(p) for p in re.findall(r"Zenoh router on \S+ \(pid (\d+)\)", self.output)]
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(30)
            except subprocess.TimeoutExpired:
                pids.append(self.proc.pid)
        for pid in pids:  # each leads its own process group
            if not _alive(pid):
                continue
            try:
                os.killpg(pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        self.proc.wait(10)
        self.discovery.close()


@pytest.fixture(scope="module")
def robots(tmp_path_factory: pytest.TempPathFactory, plain_wheel: Path
           ) -> Iterator[dict[str, Future[Launch]]]:
    """Both cases prepared side by side, each in a folder of its own: installed, checked and
    launched (``_editable``, ``_plain``). A test takes its own case's launch (``.result()``
    raises what failed in its preparation); every launch is stopped at the module's end."""
    launched: list[Launch] = []
    cases: dict[str, Callable[[Path], Launch]] = {
        "editable": _editable, "plain": lambda tmp: _plain(tmp, plain_wheel)}

    def prepare(case: str) -> Launch:
        launched.append(cases[case](tmp_path_factory.mktemp(case)))
        return launched[-1]

    with ThreadPoolExecutor(max_workers=len(cases)) as pool:
        try:
            yield {case: pool.submit(prepare, case) for case in cases}
        finally:
            pool.shutdown(wait=True)
            for launch in launched:
                launch.stop()


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def _check_running(launch: Launch) -> None:
    """Every process of the file started once and still runs: no exit, no restart."""
    assert launch.proc.poll() is None, launch.output[-5000:]
    pids = launch.pids()
    assert set(pids) == launch.labels, (sorted(pids), sorted(launch.labels))
    restarted = {label: ps for label, ps in pids.items() if len(ps) != 1}
    assert not restarted, f"restarted: {restarted}\n{launch.output[-5000:]}"
    dead = [label for label, ps in pids.items() if not _alive(ps[0])]
    assert not dead, f"not running: {dead}\n{launch.output[-5000:]}"


def _answers(check: object, timeout: float = 20.0) -> None:
    """``check()`` passes within ``timeout`` (a door may still be finishing its start)."""
    assert callable(check)
    errors: list[BaseException] = []

    def passes() -> bool:
        try:
            check()
        except (AssertionError, OSError, httpx.HTTPError, TimeoutError, ValueError) as exc:
            errors[:] = [exc]
            return False
        return True

    assert wait_for(passes, timeout, interval=0.5), f"{check.__name__}: {errors[-1]!r}"


def _check_doors(launch: Launch) -> None:
    host = "127.0.0.1"
    ports = launch.bound()
    assert set(ports) == set(BOUND), f"the gateway logged no port for {set(BOUND) - set(ports)}"
    rest, ws, modbus, rosbridge = (ports[k] for k in BOUND)
    token: list[str] = []

    def discovery() -> None:  # the UDP broadcast names the REST port
        payload = json.loads(launch.discovery.recv(4096))
        assert payload["port"] == rest, payload

    def rest_token() -> None:
        r = httpx.get(f"http://{host}:{rest}/api/v1/token",
                      params={"username": "admin", "password": "admin"}, timeout=5)
        assert r.status_code == 200, r.text
        token[:] = [r.json()["token"]]

    def dashboard_page() -> None:
        r = httpx.get(f"http://{host}:{rest}/", timeout=5)
        assert r.status_code == 200 and "text/html" in r.headers["content-type"], r.text[:300]
        config = httpx.get(f"http://{host}:{rest}/config.json", timeout=5).json()
        assert config["rosbridge_port"] == rosbridge, config  # where the page's socket goes

    def topic_websocket() -> None:
        with connect(f"ws://{host}:{ws}/galileo/status?token={token[0]}", open_timeout=5) as c:
            assert isinstance(json.loads(c.recv(timeout=10)), dict)

    def dashboard_socket() -> None:  # rosbridge v2, what the dashboard page talks to
        with connect(f"ws://{host}:{rosbridge}", open_timeout=5) as c:
            c.send(json.dumps({"op": "call_service", "service": "/rosapi/topics", "id": "t1"}))
            deadline = time.monotonic() + 10
            while True:
                frame = json.loads(c.recv(timeout=max(0.1, deadline - time.monotonic())))
                if frame.get("op") == "service_response" and frame.get("id") == "t1":
                    break
            assert frame["result"] is True, frame
            assert "/galileo/status" in frame["values"]["topics"], frame

    def modbus_tcp() -> None:
        client = ModbusTcpClient(host, port=modbus, timeout=5)
        try:
            assert client.connect(), "Modbus TCP: cannot connect"
            rr = client.read_input_registers(0, count=27, device_id=1)
            assert not rr.isError(), rr
            assert len(rr.registers) == 27, rr
        finally:
            client.close()

    for check in (rest_token, dashboard_page, topic_websocket, dashboard_socket, modbus_tcp,
                  discovery):
        _answers(check)


def _run_sim(launch: Launch) -> None:
    assert wait_for(lambda: launch.ready() or launch.proc.poll() is not None, 120,
                    interval=0.2), launch.output[-5000:]
    assert launch.ready(), launch.output[-5000:]
    # The checks are of a sim that has run RUN_FOR seconds (a crash loop would show by then).
    wait_for(lambda: time.monotonic() - launch.started >= RUN_FOR or
             launch.proc.poll() is not None, RUN_FOR + 5, interval=0.5)
    _check_doors(launch)
    _check_running(launch)


def _editable(tmp: Path) -> Launch:
    """``pip install -e .`` (no extras) and ``zenros launch deploy/launch/sim.yaml``."""
    inst = _install(tmp, wheel=None)
    outside = tmp / "elsewhere"
    outside.mkdir()
    _check_imports(inst, outside, editable=True)
    return Launch(inst, "deploy/launch/sim.yaml", inst.src, tmp / "home")


def _plain(tmp: Path, wheel: Path) -> Launch:
    """``pip install <checkout>`` (not editable, no extras), then ``zenros launch sim.yaml`` in
    a folder outside the checkout: the launch file and the map come from the install."""
    inst = _install(tmp, wheel)
    outside = tmp / "elsewhere"
    outside.mkdir()
    _check_imports(inst, outside, editable=False)
    r = inst.run(str(inst.bin / "zenros"), "launch", "--list", cwd=outside)
    assert r.returncode == 0 and re.search(r"^\s+sim\.yaml\s+\S", r.stdout, re.MULTILINE), r
    return Launch(inst, "sim.yaml", outside, tmp / "home")


@pytest.mark.timeout(900)  # the two cases are prepared side by side
def test_readme_command_1_gives_a_working_robot(robots: dict[str, Future[Launch]]) -> None:
    """``pip install -e .`` (no extras) and ``zenros launch deploy/launch/sim.yaml``."""
    _run_sim(robots["editable"].result())


@pytest.mark.timeout(900)  # the two cases are prepared side by side
def test_a_plain_install_runs_the_sim_by_name_from_anywhere(
    robots: dict[str, Future[Launch]]
) -> None:
    """``pip install <checkout>`` (not editable, no extras), then ``zenros launch sim.yaml`` in
    a folder outside the checkout: the launch file and the map come from the install."""
    _run_sim(robots["plain"].result())
