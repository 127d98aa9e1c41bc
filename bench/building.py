"""Building benchmark: a goal two floors up in the demo tower (docs/building.md), through the
robot API as a user sends it, and two robots sharing the lift.

Prints one JSON line with:

- ``building_reached``: the goal on floor 3 from floor 1 (`deploy/launch/building.yaml
  speed:=10`, ``POST /navigation/start_nav_task {"map": "floor3", ...}``): ``1 of 1``.
- ``building_goal_sim_s`` / ``building_goal_wall_s``: sim and wall seconds from the goal sent
  to the task COMPLETE (sim: the launch's ``/clock``).
- ``building_board_sim_s``: of those, from the car standing open for the robot at level 1
  (``WAITING_IN``) to its doors closing with the robot aboard (the drive in);
  ``building_ride_sim_s``: from there to the car standing open at level 3
  (``WAITING_OUT``); the reference in the same run, ``building_ride_ideal_s``: what the car
  needs at the least for the same stages (doors closing, two floors of travel, doors
  opening), from the building file.
- ``elevator_share``: two robots of `fleet.yaml building:=...` (wall clock) sent to floor 3
  at once, both through the one lift (capacity 1): how many reached (``2 of 2``), and
  ``elevator_share_wall_s`` from the goals sent to the last COMPLETE, against
  ``elevator_alone_wall_s`` (robot1 alone, the same goal, in the same launch beforehand).

Run: ``python bench/building.py [--no-share]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import httpx
from _harness import emit, free_port, unique_prefix
from zenros.building import load_building
from zenros.context import Context
from zenros.msgs.rosgraph_msgs import Clock
from zenros.msgs.zenros_msgs import ElevatorState
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.session import SessionOptions
from zenros.testing import Proc, store_on_master

ROOT = Path(__file__).resolve().parents[1]
TOWER = ROOT / "deploy" / "buildings" / "tower" / "tower.yaml"
FLOOR1 = ROOT / "deploy" / "buildings" / "tower" / "floor1" / "floor1.yaml"
GOAL = {"x": 10.0, "y": 0.0, "theta": 0.0, "map": "floor3"}


def launch(home: Path, file: str, *args: str) -> tuple[Proc, str, dict[str, str]]:
    rest = free_port()
    env = {**os.environ, "ZENROS_HOME": str(home), "ZENROS_PREFIX": unique_prefix(),
           "ZENROS_CONNECT": f"tcp/127.0.0.1:{free_port()}"}
    ports = {"rest_port": rest, "ws_port": free_port(), "modbus_port": free_port(),
             "rosbridge_port": free_port()}
    store_on_master(env["ZENROS_HOME"], env["ZENROS_PREFIX"],
                    {f"/gateway/{k}": v for k, v in ports.items()})
    proc = Proc([sys.executable, "-m", "zenros.cli", "launch", str(ROOT / "deploy" / "launch"
                                                                    / file),
                 *args, *(f"{k}:={v}" for k, v in ports.items())], env=env)
    return proc, f"http://127.0.0.1:{rest}/api/v1", env


def wait_up(http: httpx.Client, api: str, base: str, timeout: float = 180.0) -> None:
    """Wait for robot ``base`` on floor 1; sets ``http``'s token from gateway ``api``."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        try:
            if not http.params.get("token"):
                http.params = {"token": http.get(f"{api}/token", params={
                    "username": "admin", "password": "admin"}).json()["token"]}
            if http.get(f"{base}/navigation/current_map").json().get("name") == "floor1":
                return
        except (httpx.HTTPError, ValueError, KeyError):
            pass
        time.sleep(0.5)
    raise RuntimeError(f"{base} not up within {timeout:g} s")


def start(http: httpx.Client, base: str, goal: dict[str, Any], timeout: float = 120.0) -> str:
    """Start a goal's task; a service still coming up (503) is asked again."""
    end = time.monotonic() + timeout
    while True:
        r = http.post(f"{base}/navigation/start_nav_task", json=goal)
        if r.status_code != 503 or time.monotonic() > end:
            if r.status_code != 200:
                raise RuntimeError(f"{base}: {r.status_code} {r.text}")
            return str(r.json()["id"])
        time.sleep(1.0)


def run_goals(http: httpx.Client, bases: list[str], timeout: float = 600.0) -> list[str]:
    ids = [start(http, base, {**GOAL, "x": GOAL["x"] - 4.0 * i})  # one goal each, 4 m apart
           for i, base in enumerate(bases)]
    end = time.monotonic() + timeout
    states = ["" for _ in bases]
    docs: list[Any] = [None for _ in bases]
    while time.monotonic() < end and not all(s in ("COMPLETE", "ERROR", "CANCELLED")
                                             for s in states):
        for i, (base, task) in enumerate(zip(bases, ids, strict=True)):
            r = http.get(f"{base}/task", params={"id": task})
            if r.status_code != 200:  # the robot's tasks service briefly out of reach: again
                print(f"{base}/task: {r.status_code} {r.text}", file=sys.stderr)
                continue
            docs[i] = r.json()
            states[i] = docs[i]["state"]
        time.sleep(0.2)
    for base, state, doc in zip(bases, states, docs, strict=True):
        if state != "COMPLETE":  # say why on stderr: the figure alone would not
            print(f"{base}: {state}: "
                  f"{[t.get('result') for t in (doc or {}).get('sub_tasks', [])]}",
                  file=sys.stderr)
    return states


def single(tmp: Path) -> dict[str, Any]:
    proc, base, env = launch(tmp / "one", "building.yaml", "speed:=10")
    ctx = Context(prefix=env["ZENROS_PREFIX"],
                  options=SessionOptions(connect=[env["ZENROS_CONNECT"]]))
    node = Node("building_bench", context=ctx)
    clock: list[float] = [0.0]
    marks: dict[str, float] = {}
    node.create_subscription(Clock, "/clock",
                             lambda m: clock.__setitem__(0, m.clock.nanoseconds / 1e9))

    def on_car(s: ElevatorState) -> None:
        marks.setdefault("car", clock[0])
        if s.state == "WAITING_IN" and s.level == 1 and s.door >= 0.999:
            marks.setdefault("in", clock[0])
        if "in" in marks and s.level == 1 and s.riders and s.door < 0.999:
            marks.setdefault("closing", clock[0])  # the robot aboard, the doors closing
        if s.state == "WAITING_OUT" and s.level == 3 and s.door >= 0.999:
            marks.setdefault("out", clock[0])

    node.create_subscription(ElevatorState, "/building/elevators/lift1/state", on_car,
                             QOS_LATCHED)
    try:
        with httpx.Client(timeout=30) as http:
            wait_up(http, base, base)
            end = time.monotonic() + 60
            while (not clock[0] or "car" not in marks) and time.monotonic() < end:
                time.sleep(0.1)  # the clock and the car heard: the building is up
            t0, s0 = time.monotonic(), clock[0]
            (state,) = run_goals(http, [base])
            wall, sim = time.monotonic() - t0, clock[0] - s0
    finally:
        node.close()
        ctx.close()
        proc.stop(timeout=30)
    e = load_building(TOWER).elevator()
    return {"building_reached": f"{int(state == 'COMPLETE')} of 1",
            "building_goal_sim_s": round(sim, 1), "building_goal_wall_s": round(wall, 1),
            "building_board_sim_s": (round(marks["closing"] - marks["in"], 1)
                                     if {"in", "closing"} <= marks.keys() else None),
            "building_ride_sim_s": (round(marks["out"] - marks["closing"], 1)
                                    if {"closing", "out"} <= marks.keys() else None),
            "building_ride_ideal_s": 2 * e.door_s + 2 * e.travel_s}


def shared(tmp: Path) -> dict[str, Any]:
    proc, base, _ = launch(tmp / "two", "fleet.yaml", "robots:=2", f"building:={TOWER}",
                           f"map:={FLOOR1}")
    try:
        with httpx.Client(timeout=30) as http:
            bases = [f"{base}/robots/robot{k}" for k in (1, 2)]
            for b in bases:
                wait_up(http, base, b)
            t0 = time.monotonic()
            (alone,) = run_goals(http, bases[:1])
            alone_s = time.monotonic() - t0
            # robot1 back down first: both start on floor 1
            back = {"x": 0.0, "y": 0.0, "theta": 0.0, "map": "floor1"}
            task = start(http, bases[0], back)
            end = time.monotonic() + 600
            while time.monotonic() < end and http.get(
                    f"{bases[0]}/task", params={"id": task}).json()["state"] not in (
                    "COMPLETE", "ERROR", "CANCELLED"):
                time.sleep(0.2)
            t0 = time.monotonic()
            states = run_goals(http, bases)
            both_s = time.monotonic() - t0
    finally:
        proc.stop(timeout=30)
    return {"elevator_share": f"{states.count('COMPLETE')} of 2",
            "elevator_share_wall_s": round(both_s, 1),
            "elevator_alone_wall_s": round(alone_s, 1) if alone == "COMPLETE" else None}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-share", action="store_true", help="skip the two-robot run")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        figures = single(Path(tmp))
        if not args.no_share:
            figures.update(shared(Path(tmp)))
    emit("building", figures)


if __name__ == "__main__":
    main()
