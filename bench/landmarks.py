"""Landmark benchmark: reflector detection and relocalisation on the demo office, no network.

Random poses in the corridor and the lobby (any heading), the simulated laser (360 beams,
12 m, ``range_noise`` 0.01 m) casting ranges and intensities against the office's
``landmarks.yaml``; prints one JSON line with:

- ``visible_mean``: reflectors in line of sight within range per scan;
- ``hit_rate``: detected / in line of sight within ``--reach`` m (the detector finds what the
  beams fall on; past a few metres a 10 cm strip seen at a slant falls between beams);
  ``false_detections``: detections farther than 10 cm from every reflector;
- ``xy_p50``, ``xy_p95``, ``xy_max`` (m) and ``deg_p95``, ``deg_max``: the fix's error, the
  estimate 1 m and 20 degrees off; ``fixed``: fixes / poses; ``fixed_blind``: the same with
  no estimate (ambiguous poses refused);
- ``intensities_ms``, ``detect_ms``, ``locate_ms``: the median cost per scan.

Run: ``python bench/landmarks.py [--poses N] [--seed S] [--reach M]``.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import time

import numpy as np
from zenros.maps import load_landmarks, load_map
from zenros.se2 import Pose2, angle_diff
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.reflectors import Reflectors
from zenros.services.chassis.world import World
from zenros.services.nav.localization.landmarks import LandmarkError, locate
from zenros.services.nav.localization.reflectors import detect
from zenros.services.nav.params import DEMO_MAP

MOUNT = Pose2(0.1, 0.0, 0.0)


def main(poses: int, seed: int, reach: float) -> dict[str, float]:
    cfg = LaserConfig(noise=0.01)
    world = World(load_map(DEMO_MAP))
    laser = Laser(world, cfg, np.random.default_rng(seed))
    marks = load_landmarks(DEMO_MAP)
    refl = Reflectors(marks)
    xy = np.array([(m.x, m.y) for m in marks])
    angles = cfg.angle_min + np.arange(cfg.beams) * cfg.angle_increment
    rng = np.random.default_rng(seed)
    visible, reachable, hits, false, errs, degs = [], 0, 0, 0, [], []
    t_int, t_det, t_loc = [], [], []
    fixed = blind = 0
    for _ in range(poses):
        if rng.random() < 0.8:
            truth = Pose2(rng.uniform(-2, 25), rng.uniform(-0.8, 0.8), rng.uniform(-3.1, 3.1))
        else:
            truth = Pose2(rng.uniform(18, 24), rng.uniform(-5, -2), rng.uniform(-3.1, 3.1))
        lp = truth * MOUNT
        ranges = laser.ranges(lp.x, lp.y, lp.theta)
        t0 = time.perf_counter()
        inten = refl.intensities(lp.x, lp.y, lp.theta, angles, ranges, cfg.range_max)
        t1 = time.perf_counter()
        found = detect(ranges, inten, cfg.angle_min, cfg.angle_increment, cfg.range_min,
                       cfg.range_max, MOUNT)
        t2 = time.perf_counter()
        t_int.append((t1 - t0) * 1e3)
        t_det.append((t2 - t1) * 1e3)
        # reflectors in line of sight: the wall along their bearing is no nearer than they
        d = np.hypot(xy[:, 0] - lp.x, xy[:, 1] - lp.y)
        bearing = np.arctan2(xy[:, 1] - lp.y, xy[:, 0] - lp.x)
        wall = laser.cast_map(lp.x, lp.y, bearing)
        sight = (d <= cfg.range_max) & (wall >= d - 0.03)
        visible.append(int(sight.sum()))
        seen = np.array([truth.apply(x, y) for x, y in found.xy]).reshape(-1, 2)
        near = np.hypot(seen[:, None, 0] - xy[None, :, 0], seen[:, None, 1] - xy[None, :, 1])
        false += int((near.min(axis=1, initial=np.inf) > 0.1).sum()) if len(seen) else 0
        close = sight & (d <= reach)
        reachable += int(close.sum())
        if len(seen):
            hits += int((close & (near.min(axis=0) <= 0.1)).sum())
        rough = Pose2(truth.x + 0.8, truth.y - 0.6, truth.theta + math.radians(20))
        t3 = time.perf_counter()
        try:
            fix = locate(found.xy, xy, rough)
        except LandmarkError:
            fix = None
        t_loc.append((time.perf_counter() - t3) * 1e3)
        if fix is not None:
            fixed += 1
            errs.append(truth.distance(fix.pose))
            degs.append(abs(math.degrees(angle_diff(fix.pose.theta, truth.theta))))
        try:
            locate(found.xy, xy, None)
            blind += 1
        except LandmarkError:
            pass
    e, g = np.array(errs), np.array(degs)
    return {
        "poses": poses, "visible_mean": round(float(np.mean(visible)), 2),
        "reach_m": reach, "hit_rate": round(hits / max(reachable, 1), 3),
        "false_detections": false, "fixed": round(fixed / poses, 3),
        "fixed_blind": round(blind / poses, 3),
        "xy_p50": round(float(np.percentile(e, 50)), 4),
        "xy_p95": round(float(np.percentile(e, 95)), 4), "xy_max": round(float(e.max()), 4),
        "deg_p95": round(float(np.percentile(g, 95)), 3), "deg_max": round(float(g.max()), 3),
        "intensities_ms": round(statistics.median(t_int), 3),
        "detect_ms": round(statistics.median(t_det), 3),
        "locate_ms": round(statistics.median(t_loc), 2),
        "locate_ms_p95": round(float(np.percentile(t_loc, 95)), 2),
    }


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    ap.add_argument("--poses", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--reach", type=float, default=4.0)
    args = ap.parse_args()
    print(json.dumps(main(args.poses, args.seed, args.reach)))
