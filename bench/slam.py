"""SLAM benchmark: a noisy lap of the demo office, mapped by the slam service's mapper and by
a reference (the same scan matcher without loop closure), with the figures of issue 39.

The lap: the chassis simulator's own classes (`ChassisParameters` → `Simulation`: world,
laser, noisy odometry, drive limits) run in process with ``odom_noise`` 0.05 and
``range_noise`` 0.02, driven round the desk block south of the corridor (corridor → door →
round the desks → right-hand hall → corridor → start, about 55 m) by a pure-pursuit driver
that sees the true pose, as a person with a joystick would. Its scans (10 Hz, 360 beams)
and odometry go to the service's `MappingSession` (what the node feeds), paced at ``speed``
sim seconds per wall second (10 by default, as ``speed:=10``).

Prints one JSON line:

- ``slam_max_pose_err_m`` / ``slam_max_yaw_err_deg``: the largest error, over every scan of
  the lap, of the mapped base pose (each scan at its node's corrected pose plus the odometry
  since) against the simulator's truth, both in the map frame (the robot's start pose);
  ``slam_online_max_pose_err_m``: the same for the pose the mapper gave when the scan came.
- ``slam_wall_f1`` (and ``_precision``/``_recall``): the built map's occupied cells against
  the world's, 1-cell tolerance (8-neighbourhood), 0.05 m cells, the built map put in the
  world by the start pose (specs/mapping.md, section 9). Recall counts the world's occupied cells
  the laser saw (the cells the noiseless beams of the lap end in).
- ``slam_scan_ms_p50`` / ``_p95``: ms of the worker thread's CPU time (``time.thread_time``,
  so other work on a shared machine does not count) to fold in one scan that becomes a node
  (match, loop attempt, a closure's optimisation); the ray casting of new nodes into the grid
  happens when the map is next read (every ``map_update_interval``, as slam_toolbox builds its
  map): ``slam_map_update_ms_p50``/``_max`` are those reads (CPU ms; after a closure every
  node is cast again);
  ``slam_odometry_only_scans``: the scans taken before the base had moved enough for a new
  node (Karto's gating), which only move the pose by odometry, at once.
- ``slam_keeps_up``: no scan skipped by the worker at ``speed``; ``slam_max_lag_ms``.
- ``slam_loop_closures``, ``slam_nodes``, and the reference's ``ref_*`` figures.

Run: ``python bench/slam.py [--speed 10] [--seed 7]``. Other figures (the exploration keys)
join the line through `FIGURES`.
"""

from __future__ import annotations

import argparse
import logging
import math
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import msgspec
import numpy as np
from scipy import ndimage
from zenros.se2 import Pose2, wrap_angle
from zenros.services.chassis.config import ChassisParameters, chassis_config
from zenros.services.chassis.laser import Laser
from zenros.services.chassis.sim import Simulation
from zenros.services.slam.graph import relative
from zenros.services.slam.mapper import Mapper, ScanOutcome
from zenros.services.slam.params import SlamParameters
from zenros.services.slam.session import MappingSession

sys.path.insert(0, str(Path(__file__).parent))
from _harness import emit

# corridor east, through the door at x 8, round the desks, the right-hand hall, and back
LAP = [(8.0, 0.0), (8.0, -2.3), (6.75, -3.1), (6.75, -8.4), (16.0, -8.4), (16.0, -6.75),
       (18.6, -6.75), (18.6, 0.0), (0.0, 0.0)]
RATE = 50.0
SCAN_EVERY = 5
CRUISE = 0.8

FIGURES: list[Callable[[argparse.Namespace], dict[str, Any]]] = []
"""More figures for the line: each is called with the parsed arguments and returns its keys
(the exploration figures join here)."""


@dataclass
class Lap:
    sim: Simulation
    start: Pose2
    stamps: list[float]
    odom: list[Pose2]
    truth: list[Pose2]
    ranges: list[np.ndarray]
    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float


def _drive(sim: Simulation, goal: tuple[float, float], last: bool) -> tuple[float, float]:
    p = sim.truth
    dx, dy = goal[0] - p.x, goal[1] - p.y
    err = wrap_angle(math.atan2(dy, dx) - p.theta)
    if abs(err) > 0.5:
        return 0.0, 1.2 * math.copysign(1.0, err)
    dist = math.hypot(dx, dy)
    v = min(CRUISE, 1.0 * dist + (0.0 if last else 0.3))
    return v, 2.0 * err


def make_lap(seed: int, odom_noise: float, range_noise: float) -> Lap:
    """Drive the lap in the simulator, recording every scan with its odometry and truth."""
    params = ChassisParameters(odom_noise=odom_noise, range_noise=range_noise, seed=seed)
    sim = chassis_config(params).build(logging.getLogger("bench.slam"))
    cfg = sim.laser.config
    lap = Lap(sim, sim.truth, [], [], [], [], cfg.angle_min, cfg.angle_increment,
              cfg.range_min, cfg.range_max)
    dt = 1.0 / RATE
    step = 0
    for k, goal in enumerate(LAP):
        last = k == len(LAP) - 1
        while sim.truth.distance(Pose2(goal[0], goal[1])) > (0.1 if last else 0.25):
            v, w = _drive(sim, goal, last)
            sim.drive.command(v, w, sim.time)
            sim.step(dt)
            step += 1
            if step % SCAN_EVERY == 0:
                lap.stamps.append(sim.time)
                lap.odom.append(sim.odometry.pose)
                lap.truth.append(sim.truth)
                lap.ranges.append(sim.scan())
            if sim.bumper or sim.time > 600:
                raise RuntimeError(f"the lap's driver got stuck at {sim.truth}")
    return lap


@dataclass
class Run:
    mapper: Mapper
    online: list[Pose2]
    node_ms: list[float]
    map_ms: list[float]
    moved_only: int
    skipped: int
    max_lag: float


def run_mapper(lap: Lap, params: SlamParameters, speed: float) -> Run:
    """Feed the lap through the service's `MappingSession` (odometry, then each scan, as the
    node does) at ``speed`` sim seconds per wall second (0: each scan as soon as the last
    one is folded in)."""
    online: list[Pose2] = [Pose2()] * len(lap.stamps)
    index = {t: k for k, t in enumerate(lap.stamps)}

    def folded(out: ScanOutcome, stamp: float) -> None:
        online[index[stamp]] = out.pose

    session = MappingSession(params, folded)
    session.mount = lap.sim.laser_mount
    session.begin()
    map_ms: list[float] = []
    next_map = lap.stamps[0]
    t_start = time.perf_counter()
    for k, stamp in enumerate(lap.stamps):
        if speed > 0:
            pause = t_start + (stamp - lap.stamps[0]) / speed - time.perf_counter()
            if pause > 0:
                time.sleep(pause)
        session.on_odom(stamp, lap.odom[k])
        session.on_scan(stamp, lap.ranges[k], lap.angle_min, lap.angle_increment,
                        lap.range_min, lap.range_max)
        if speed <= 0:
            session.worker.wait_idle(600)
        if stamp >= next_map:  # the node's map update, every map_update_interval
            t0 = time.thread_time()
            session.snapshot()
            map_ms.append((time.thread_time() - t0) * 1e3)
            next_map = stamp + params.map_update_interval
    session.worker.wait_idle(600)
    run = Run(session.mapper, online, list(session.node_cpu_ms), map_ms, session.moved_only,
              session.skipped, session.worker.max_lag)
    session.close()
    return run


def final_poses(lap: Lap, mapper: Mapper) -> list[Pose2]:
    """Each scan at its latest node's corrected pose plus the odometry since that node."""
    nodes = mapper.graph.nodes
    out = []
    k = -1
    for i, stamp in enumerate(lap.stamps):
        while k + 1 < len(nodes) and nodes[k + 1].stamp <= stamp:
            k += 1
        if k < 0:
            out.append(lap.odom[i])
            continue
        out.append(nodes[k].pose * relative(nodes[k].odom, lap.odom[i]))
    return out


def pose_errors(lap: Lap, poses: list[Pose2]) -> tuple[float, float]:
    """Max position (m) and heading (deg) error against truth in the map frame."""
    inv = lap.start.inverse()
    dp, da = 0.0, 0.0
    for est, truth in zip(poses, lap.truth, strict=True):
        t = inv * truth
        dp = max(dp, math.hypot(est.x - t.x, est.y - t.y))
        da = max(da, abs(wrap_angle(est.theta - t.theta)))
    return dp, math.degrees(da)


def seen_walls(lap: Lap) -> np.ndarray:
    """The world's occupied cells that the lap's noiseless beams end in."""
    world = lap.sim.world
    clean = Laser(world, replace(lap.sim.laser.config, noise=0.0))
    seen = np.zeros(world.solid.shape, dtype=bool)
    for truth in lap.truth:
        p = truth * lap.sim.laser_mount
        r = clean.ranges(p.x, p.y, p.theta).astype(np.float64)
        a = p.theta + lap.angle_min + np.arange(len(r)) * lap.angle_increment
        ok = np.isfinite(r)
        # just past the surface, inside the cell the beam entered
        ex = p.x + (r[ok] + 1e-3) * np.cos(a[ok])
        ey = p.y + (r[ok] + 1e-3) * np.sin(a[ok])
        rows = np.floor((ey - world.oy) / world.res).astype(int)
        cols = np.floor((ex - world.ox) / world.res).astype(int)
        inside = (rows >= 0) & (rows < world.height) & (cols >= 0) & (cols < world.width)
        seen[rows[inside], cols[inside]] = True
    return seen & world.solid


def wall_f1(lap: Lap, mapper: Mapper, seen: np.ndarray) -> tuple[float, float, float]:
    """Precision, recall, F1 of the built map's occupied cells (1-cell tolerance)."""
    world = lap.sim.world
    grid = mapper.grid
    occ = grid.occupancy() == 100
    rows, cols = np.nonzero(occ)
    if not len(rows):
        return 0.0, 0.0, 0.0
    # built cell centres, map frame → world
    mx = grid.ox + (cols + 0.5) * grid.res
    my = grid.oy + (rows + 0.5) * grid.res
    s = lap.start
    c, sn = math.cos(s.theta), math.sin(s.theta)
    wx, wy = s.x + c * mx - sn * my, s.y + sn * mx + c * my
    wr = np.floor((wy - world.oy) / world.res).astype(int)
    wc = np.floor((wx - world.ox) / world.res).astype(int)
    inside = (wr >= 0) & (wr < world.height) & (wc >= 0) & (wc < world.width)
    near_true = ndimage.binary_dilation(world.solid, structure=np.ones((3, 3), bool))
    precision = float(np.count_nonzero(near_true[wr[inside], wc[inside]])) / len(wr)
    built = np.zeros(world.solid.shape, dtype=bool)
    built[wr[inside], wc[inside]] = True
    near_built = ndimage.binary_dilation(built, structure=np.ones((3, 3), bool))
    recall = float(np.count_nonzero(near_built & seen)) / max(1, int(seen.sum()))
    f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
    return precision, recall, f1


def figures(prefix: str, lap: Lap, run: Run, seen: np.ndarray, speed: float) -> dict[str, Any]:
    final = final_poses(lap, run.mapper)
    dp, da = pose_errors(lap, final)
    op, oa = pose_errors(lap, run.online)
    pr, rc, f1 = wall_f1(lap, run.mapper, seen)
    return {
        f"{prefix}_max_pose_err_m": round(dp, 4),
        f"{prefix}_max_yaw_err_deg": round(da, 3),
        f"{prefix}_online_max_pose_err_m": round(op, 4),
        f"{prefix}_online_max_yaw_err_deg": round(oa, 3),
        f"{prefix}_wall_f1": round(f1, 4),
        f"{prefix}_wall_precision": round(pr, 4),
        f"{prefix}_wall_recall": round(rc, 4),
        f"{prefix}_scan_ms_p50": round(statistics.median(run.node_ms), 3),
        f"{prefix}_scan_ms_p95": round(float(np.percentile(run.node_ms, 95)), 3),
        f"{prefix}_map_update_ms_p50": round(statistics.median(run.map_ms), 2),
        f"{prefix}_map_update_ms_max": round(max(run.map_ms), 2),
        f"{prefix}_odometry_only_scans": run.moved_only,
        f"{prefix}_keeps_up": run.skipped == 0,
        f"{prefix}_skipped": run.skipped,
        f"{prefix}_max_lag_ms": round(run.max_lag * 1e3, 2),
        f"{prefix}_nodes": run.mapper.nodes,
        f"{prefix}_loop_closures": run.mapper.loop_closures,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed", type=float, default=10.0, help="sim seconds per wall second")
    ap.add_argument("--seed", type=int, default=7, help="noise seed")
    ap.add_argument("--odom-noise", type=float, default=0.05)
    ap.add_argument("--range-noise", type=float, default=0.02)
    ap.add_argument("--no-explore", action="store_true",
                    help="leave out the exploration keys (bench/explore.py: minutes of sim)")
    args = ap.parse_args()
    if not args.no_explore:
        from explore import figures as explore_figures  # bench/explore.py, beside this one
        FIGURES.append(explore_figures)
    lap = make_lap(args.seed, args.odom_noise, args.range_noise)
    seen = seen_walls(lap)
    params = SlamParameters()
    slam = run_mapper(lap, params, args.speed)
    ref = run_mapper(lap, msgspec.structs.replace(params, do_loop_closing=False), args.speed)
    odom_err = pose_errors(lap, lap.odom)
    out: dict[str, Any] = {
        **figures("slam", lap, slam, seen, args.speed),
        **figures("ref", lap, ref, seen, args.speed),
        "odom_max_pose_err_m": round(odom_err[0], 4),
        "odom_max_yaw_err_deg": round(odom_err[1], 3),
        "lap_m": round(sum(a.distance(b) for a, b in zip(lap.truth, lap.truth[1:])), 1),
        "lap_sim_s": round(lap.stamps[-1] - lap.stamps[0], 1),
        "scans": len(lap.stamps),
        "speed": args.speed, "seed": args.seed,
        "odom_noise": args.odom_noise, "range_noise": args.range_noise,
        "reference": "the same mapper with do_loop_closing false (scan matching only)",
    }
    for extra in FIGURES:
        out.update(extra(args))
    emit("slam", out)


if __name__ == "__main__":
    main()
