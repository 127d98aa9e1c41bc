"""A robot host's link pulled and restored, seen from the station (`demo.sh outage`).

Runs on the station of the routed demo (ZR_TOPOLOGY=routed), as a client of the station's
router. It follows every robot's odom and the graph, then:

1. waits until every robot is in the graph and its odom flows, and takes a baseline rate;
2. sends each robot but the cut one a goal 1 m away through the fleet gateway (REST);
3. pulls the cut robot's link (``demo.sh link ROBOT down``) for ``--seconds``, restores it;
4. waits until the cut robot is back in the graph with its odom flowing, and the goals done.

Prints one JSON line: per robot the odom rate before and during the outage and the longest
gap during it, when the cut robot left the graph (after the pull) and came back (after the
restore), when its odom came back, and each goal's time to complete. Exits 1 if something
did not happen within its time (the JSON says what).
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from typing import Any

from zenros.context import Context
from zenros.msgs.nav_msgs import Odometry
from zenros.node import Node
from zenros.session import add_session_arguments, options_from_args

API = "http://127.0.0.1:3546/api/v1"  # the fleet gateway on the station (fleet.yaml)
STEP = 1.0  # m: each goal, along the corridor from where the robot is
READY_S = 60.0  # every robot in the graph with odom flowing, and its API answering
BACK_S = 30.0  # the cut robot back after the restore; the goals complete


class Rest:
    """The fleet gateway's robot API, with a token (the default admin/admin)."""

    def __init__(self) -> None:
        self.token = ""

    def call(self, method: str, path: str, body: dict[str, Any] | None = None) -> tuple[int, Any]:
        if not self.token:
            status, doc = self._call("GET", "/token?username=admin&password=admin", None)
            if status != 200:
                return status, doc
            self.token = doc["token"]
        sep = "&" if "?" in path else "?"
        status, doc = self._call(method, f"{path}{sep}token={self.token}", body)
        if status == 401:
            self.token = ""
        return status, doc

    @staticmethod
    def _call(method: str, path: str, body: dict[str, Any] | None) -> tuple[int, Any]:
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(API + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(req, timeout=10) as r:
                return r.status, json.loads(r.read() or b"null")
        except urllib.error.HTTPError as e:
            return e.code, e.read().decode(errors="replace")
        except (OSError, ValueError) as e:
            return 0, f"{type(e).__name__}: {e}"


class Odom:
    """Arrival times of each robot's odom at the station."""

    def __init__(self, node: Node, robots: list[str]) -> None:
        self.times: dict[str, list[float]] = {r: [] for r in robots}
        self._lock = threading.Lock()
        for r in robots:
            node.create_subscription(Odometry, f"/{r}/odom", self._on(r), 10)

    def _on(self, robot: str) -> Any:
        def got(_msg: Odometry) -> None:
            with self._lock:
                self.times[robot].append(time.monotonic())
        return got

    def between(self, robot: str, t0: float, t1: float) -> list[float]:
        with self._lock:
            return [t for t in self.times[robot] if t0 <= t <= t1]

    def flowing_since(self, robot: str, t: float) -> bool:
        """Odom arrived in the last 0.5 s, and at least 5 samples since ``t``."""
        now = time.monotonic()
        seen = self.between(robot, t, now)
        return len(seen) >= 5 and now - seen[-1] < 0.5


def rate_and_gap(times: list[float], t0: float, t1: float) -> tuple[float, float]:
    """Samples a second over [t0, t1], and the longest silence in it (edges included)."""
    edges = [t0, *times, t1]
    gap = max(b - a for a, b in itertools.pairwise(edges))
    return len(times) / (t1 - t0), gap


def until(pred: Any, timeout: float, step: float = 0.1) -> float | None:
    """Poll ``pred`` until true; the monotonic time it became true, or None."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if pred():
            return time.monotonic()
        time.sleep(step)
    return None


def send_goal(rest: Rest, robot: str) -> str:
    """A nav task STEP metres along the corridor (back towards the start past 2 m)."""
    status, pose = rest.call("GET", f"/robots/{robot}/navigation/pose")
    if status != 200:
        raise RuntimeError(f"{robot}'s pose: {status} {pose}")
    x = pose["x"] + (STEP if pose["x"] < 2.0 else -STEP)
    status, task = rest.call("POST", f"/robots/{robot}/navigation/start_nav_task",
                             {"x": x, "y": pose["y"], "theta": 0.0})
    if status != 200:
        raise RuntimeError(f"{robot}'s goal: {status} {task}")
    return str(task["id"])


def task_state(rest: Rest, robot: str, task_id: str) -> str:
    status, doc = rest.call("GET", f"/robots/{robot}/task?id={task_id}")
    return str(doc["state"]) if status == 200 else f"HTTP {status}"


def link(demo: str, robot: str, state: str) -> None:
    subprocess.run([demo, "link", robot, state], check=True, stdout=subprocess.DEVNULL)


def r3(t: float | None) -> float | None:
    return None if t is None else round(t, 2)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--demo", required=True, help="demo.sh, to pull and restore the link")
    parser.add_argument("--robots", type=int, default=3)
    parser.add_argument("--cut", default="robot2", help="the robot whose link is pulled")
    parser.add_argument("--seconds", type=float, default=10.0, help="how long it stays down")
    parser.add_argument("--baseline", type=float, default=2.0, help="seconds of odom before")
    add_session_arguments(parser)
    args = parser.parse_args()
    robots = [f"robot{k}" for k in range(1, args.robots + 1)]
    others = [r for r in robots if r != args.cut]
    out: dict[str, Any] = {"robots": args.robots, "cut": args.cut, "outage_s": args.seconds}
    rest = Rest()
    ctx = Context(options_from_args(args))
    node = Node("outage_probe", context=ctx)
    try:
        odom = Odom(node, robots)
        graph = ctx.graph

        def in_graph(r: str) -> bool:
            return f"/{r}/chassis" in graph.node_names()

        def api_up(r: str) -> bool:
            return rest.call("GET", f"/robots/{r}/navigation/pose")[0] == 200

        t_ready = time.monotonic()
        ok = until(lambda: all(in_graph(r) and odom.flowing_since(r, t_ready) for r in robots)
                   and all(api_up(r) for r in others), READY_S, 0.2)
        if ok is None:
            out["error"] = "not every robot in the graph with odom flowing and its API up"
            return 1
        time.sleep(args.baseline)  # the baseline window: what the outage is compared with
        t_down = time.monotonic()
        base = {r: rate_and_gap(odom.between(r, t_down - args.baseline, t_down),
                                t_down - args.baseline, t_down) for r in robots}
        done: dict[str, float] = {}
        goals: dict[str, str] = {}

        def all_done() -> bool:
            for r, tid in goals.items():
                if r not in done and task_state(rest, r, tid) == "COMPLETE":
                    done[r] = time.monotonic()
            return len(done) == len(goals)

        link(args.demo, args.cut, "down")
        try:
            t_down = time.monotonic()
            goals.update((r, send_goal(rest, r)) for r in others)
            t_goals = time.monotonic()
            left = until(lambda: not in_graph(args.cut), args.seconds, 0.05)
            while time.monotonic() < t_down + args.seconds:  # the outage is the scenario
                all_done()
                time.sleep(0.2)
        finally:
            link(args.demo, args.cut, "up")
        t_up = time.monotonic()
        back = until(lambda: in_graph(args.cut), BACK_S, 0.05)
        odom_back = until(lambda: odom.flowing_since(args.cut, t_up), BACK_S, 0.05)
        until(all_done, max(1.0, t_up + BACK_S - time.monotonic()), 0.2)
        during = {r: rate_and_gap(odom.between(r, t_down, t_up), t_down, t_up) for r in robots}
        cut_times = odom.between(args.cut, t_up, time.monotonic())
        out.update({
            "odom_hz_before": {r: round(base[r][0], 1) for r in robots},
            "odom_hz_during": {r: round(during[r][0], 1) for r in robots},
            "odom_max_gap_during_s": {r: round(during[r][1], 3) for r in others},
            "left_graph_after_s": r3(left and left - t_down),
            "back_in_graph_after_restore_s": r3(back and back - t_up),
            "odom_back_after_restore_s": r3(cut_times[0] - t_up if cut_times else None),
            "odom_flowing_after_restore_s": r3(odom_back and odom_back - t_up),
            "goal_complete_s": {r: r3(done[r] - t_goals) if r in done else None
                                for r in others},
            "goals_complete_before_restore": all(done.get(r, math.inf) < t_up for r in others),
            "goal_states": {r: task_state(rest, r, tid) for r, tid in goals.items()},
        })
        missing = [k for k in ("left_graph_after_s", "back_in_graph_after_restore_s",
                               "odom_flowing_after_restore_s") if out[k] is None]
        if missing or len(done) < len(goals):
            out["error"] = f"did not happen in time: {missing + sorted(set(goals) - set(done))}"
            return 1
        return 0
    finally:
        print(json.dumps(out), flush=True)
        node.close()
        ctx.close()


if __name__ == "__main__":
    sys.exit(main())
