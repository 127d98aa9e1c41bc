"""Traffic benchmark: N simulated robots with crossing goals through corridors one robot
wide, with and without schedule mode (docs/fleet.md, "Traffic schedule").

The world is generated (tests/worlds.py, `crossing_world`): two halls 3 m deep joined by
ceil(N / 2) parallel corridors, 0.8 m wide and 3 m long, 2 m apart. Robots come in pairs,
one per hall, in front of one corridor: the west one's goal is in the east hall and the east
one's in the west hall, so every pair meets head-on in its corridor unless something keeps
them apart. Every robot is a chassis and nav in this process (tests/integration/
traffic_robots.py: a session per chassis, each robot on its own sim clock at ``--speed``,
one shared world so each sees the others), plus the schedule server for the schedule run.
Times are each robot's own sim seconds (goal sent to goal ended), so a box too loaded to
keep the sims at ``--speed`` slows them without changing the figures much.

Prints one JSON line with:

- ``traffic_reached``: goals that succeeded within ``--timeout`` sim seconds in schedule
  mode, ``k of N``; ``free_reached`` the same without it.
- ``traffic_headon``: head-on meetings in schedule mode: corridors that ever held two
  robots at once (by their true poses), plus robots whose bumper ever tripped (a contact
  with a wall or a robot); ``free_headon`` the same without schedule mode, where a meeting
  is a stand-off (both stop nose to nose; nav's recoveries may or may not untangle them).
  ``*_meetings`` and ``*_bumps`` give the two parts; ``*_closest_m`` the closest two
  robots' centres came (two radii: 0.4 m).
- ``traffic_time_ratio``: in schedule mode, the mean over robots that reached of (its time
  with every robot driving) / (its time alone, without schedule mode); "alone" is measured
  once for a west and once for an east robot of corridor 0 (every corridor is the same);
  ``traffic_time_ratio_max`` the worst robot's.
- ``traffic_plan_ms_p99``: the schedule manager's time per request (CPU of its thread) at N
  robots, p99 over the schedule run's requests (``*_wall`` beside it: wall time, which a
  loaded box inflates with preemption); ``traffic_plan_ms_p99_at_50hz``: the table driven
  in-process at 50 requests a second for ``--plan-seconds`` (N robots' routes through this
  world, each robot advancing along its route between its requests), CPU and wall.

Run: ``python bench/traffic.py [--robots N] [--speed S] [--timeout S] [--no-free]``.
On this 2-core box ten robots in one process run their sims well below ``--speed``; the
docs give what was measured and at how many robots.
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
sys.path.insert(0, str(Path(__file__).parents[1] / "tests" / "integration"))

from _harness import emit, percentile
from traffic_robots import Fleet, Rect, traffic_robots
from worlds import crossing_world, lane_y
from zenros.maps import load_map
from zenros.services.schedule.segments import SegmentMap
from zenros.services.schedule.traffic import RoutePoint, TrafficTable

HALL, LENGTH, WIDTH = 3.0, 3.0, 0.8
EAST = 2 * HALL + LENGTH - 1.0
SPEED_MS = 0.5  # nav's max_linear_vel: the routes' timing


def layout(n: int) -> tuple[list[tuple[float, float, float]], list[tuple[float, float, float]]]:
    """Starts and goals of ``n`` robots: pairs in front of corridors 0, 1, ..."""
    starts, goals = [], []
    for k in range(n):
        y = lane_y(k // 2)
        if k % 2 == 0:
            starts.append((1.0, y - 0.5, 0.0))
            goals.append((EAST, y + 0.5, 0.0))
        else:
            starts.append((EAST, y - 0.5, math.pi))
            goals.append((1.0, y + 0.5, math.pi))
    return starts, goals


def corridors(lanes: int) -> list[Rect]:
    return [Rect(HALL, lane_y(k) - WIDTH / 2, HALL + LENGTH, lane_y(k) + WIDTH / 2)
            for k in range(lanes)]


def drive(fleet: Fleet, goals: list[tuple[float, float, float]], timeout: float
          ) -> dict[str, float]:
    """Send every robot its goal at once; the sim seconds each took to succeed (robots that
    failed or ran out of ``timeout`` sim seconds are left out)."""
    t0 = {n: fleet.sim_time(n) for n in fleet.names}
    handles = {n: fleet.navigate[n].send_goal_async(fleet.goal(*g))
               for n, g in zip(fleet.names, goals, strict=True)}
    took: dict[str, float] = {}
    ended: set[str] = set()
    while len(ended) < len(handles):
        for n, h in handles.items():
            if n not in ended and h.done:
                ended.add(n)
                if h.result(0).succeeded:
                    took[n] = fleet.sim_time(n) - t0[n]
        if all(fleet.sim_time(n) - t0[n] > timeout for n in fleet.names if n not in ended):
            break
        time.sleep(0.05)  # a bench polls; tests wait on conditions
    for n, h in handles.items():
        if n not in ended:
            h.cancel()
    return took


def timed(fn: Callable[..., Any], cpu: list[float], wall: list[float]) -> Callable[..., Any]:
    def wrapper(*args: Any) -> Any:
        c0, w0 = time.thread_time(), time.perf_counter()
        try:
            return fn(*args)
        finally:
            cpu.append((time.thread_time() - c0) * 1e3)
            wall.append((time.perf_counter() - w0) * 1e3)
    return wrapper


def run(home: Path, world: Path, n: int, schedule: bool, timeout: float, speed: float,
        robots: list[int] | None = None) -> dict[str, Any]:
    """One run: robots ``robots`` of the layout (all by default) drive at once."""
    starts, goals = layout(n)
    pick = robots if robots is not None else list(range(n))
    lanes = (n + 1) // 2
    cpu: list[float] = []
    wall: list[float] = []
    with traffic_robots(home, world, [starts[k] for k in pick], speed=speed,
                        schedule_mode=schedule, corridors=corridors(lanes)) as fleet:
        if fleet.server is not None:
            fleet.server.traffic.request = timed(  # type: ignore[method-assign]
                fleet.server.traffic.request, cpu, wall)
        took = drive(fleet, [goals[k] for k in pick], timeout)
        w = fleet.watch
        meetings = len({k for k, _ in w.together})
        bumps = len(w.bumped)
        return {"took": {pick[i]: took[name] for i, name in enumerate(fleet.names)
                         if name in took},
                "reached": len(took), "missed": [n for n in fleet.names if n not in took],
                "bumped": sorted(w.bumped), "meetings": meetings, "bumps": bumps,
                "closest": w.closest, "shared_holds": len(w.shared_holds),
                "plan_cpu": cpu, "plan_wall": wall}


def progress(what: str, r: dict[str, Any]) -> None:
    """One line on stderr per run, so a long bench shows where it is."""
    print(f"{what}: " + ", ".join(f"{k} {v}" for k, v in r.items()
                                   if k not in ("plan_cpu", "plan_wall")), file=sys.stderr,
          flush=True)


def plan_at_rate(world: Path, n: int, rate: float, seconds: float) -> tuple[float, float]:
    """p99 (ms) of the table's time per request, CPU and wall, driven in-process at ``rate``
    requests a second by ``n`` robots that advance along their routes."""
    segments = SegmentMap(load_map(world), world.stem)
    table = TrafficTable(segments)
    starts, goals = layout(n)
    paths = []
    for (x0, y0, _), (x1, y1, _) in zip(starts, goals, strict=True):
        ym = (y0 + y1) / 2  # into the corridor on its centre line, out of it, to the goal
        pts = [(x0, y0), (HALL - 0.3, ym), (HALL + LENGTH + 0.3, ym), (x1, y1)]
        if x0 > x1:
            pts = [(x0, y0), (HALL + LENGTH + 0.3, ym), (HALL - 0.3, ym), (x1, y1)]
        dense: list[tuple[float, float]] = []
        for (ax, ay), (bx, by) in itertools.pairwise(pts):
            m = max(1, round(math.hypot(bx - ax, by - ay) / 0.25))
            dense += [(ax + (bx - ax) * i / m, ay + (by - ay) * i / m) for i in range(m)]
        dense.append(pts[-1])
        paths.append(dense)
    cpu: list[float] = []
    wall: list[float] = []
    period, t, k = 1.0 / rate, 0.0, 0
    start = time.monotonic()
    while t < seconds:
        robot = k % n
        path = paths[robot]
        at = min(len(path) - 1, int(t * SPEED_MS / 0.25 / 2))  # half speed: some wait
        route = [RoutePoint(x, y, (i - at) * 0.25 / SPEED_MS)
                 for i, (x, y) in enumerate(path[at:], start=at)]
        c0, w0 = time.thread_time(), time.perf_counter()
        table.request(f"robot{robot + 1}", route, t, 3.0)
        cpu.append((time.thread_time() - c0) * 1e3)
        wall.append((time.perf_counter() - w0) * 1e3)
        k += 1
        t = k * period
        delay = start + t - time.monotonic()
        if delay > 0:
            time.sleep(delay)
    return percentile(cpu, 99), percentile(wall, 99)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robots", type=int, default=10)
    ap.add_argument("--speed", type=float, default=2.0, help="every chassis' sim speed")
    ap.add_argument("--timeout", type=float, default=150.0, help="sim seconds per run")
    ap.add_argument("--plan-seconds", type=float, default=20.0)
    ap.add_argument("--no-free", dest="free", action="store_false",
                    help="skip the run without schedule mode")
    args = ap.parse_args()
    n = args.robots
    home = Path(tempfile.mkdtemp(prefix="zenros-traffic-"))
    world = crossing_world(home / "world", (n + 1) // 2, width=WIDTH, length=LENGTH, hall=HALL)
    alone: dict[int, float] = {}
    for side in range(min(2, n)):
        r = run(home / f"alone{side}", world, n, False, args.timeout, args.speed, [side])
        if side not in r["took"]:
            raise RuntimeError(f"robot{side + 1} alone did not reach its goal: {r}")
        alone[side] = r["took"][side]
        progress(f"robot{side + 1} alone", r)
    sched = run(home / "schedule", world, n, True, args.timeout, args.speed)
    progress("schedule mode", sched)
    ratios = [t / alone[k % 2] for k, t in sched["took"].items()]
    p99_rate = plan_at_rate(world, n, 50.0, args.plan_seconds)
    free = run(home / "free", world, n, False, args.timeout, args.speed) if args.free else None
    if free is not None:
        progress("without schedule mode", free)
    emit("traffic", {
        "robots": n, "speed": args.speed,
        "alone_s": [round(alone[k], 1) for k in sorted(alone)],
        "traffic_time_ratio": round(statistics.mean(ratios), 2) if ratios else None,
        "traffic_time_ratio_max": round(max(ratios), 2) if ratios else None,
        "traffic_meetings": sched["meetings"], "traffic_bumps": sched["bumps"],
        "traffic_headon": sched["meetings"] + sched["bumps"],
        "traffic_closest_m": round(sched["closest"], 2),
        "traffic_shared_holds": sched["shared_holds"],
        "traffic_requests": len(sched["plan_cpu"]),
        "traffic_plan_ms_p99": round(percentile(sched["plan_cpu"], 99), 2),
        "traffic_plan_ms_p99_wall": round(percentile(sched["plan_wall"], 99), 2),
        "traffic_plan_ms_p99_at_50hz": round(p99_rate[0], 2),
        "traffic_plan_ms_p99_at_50hz_wall": round(p99_rate[1], 2),
    }, traffic_reached=f"{sched['reached']} of {n}",
        free_reached=f"{free['reached']} of {n}" if free else None,
        free_headon=free["meetings"] + free["bumps"] if free else None,
        free_meetings=free["meetings"] if free else None,
        free_bumps=free["bumps"] if free else None,
        free_closest_m=round(free["closest"], 2) if free else None)


if __name__ == "__main__":
    main()
