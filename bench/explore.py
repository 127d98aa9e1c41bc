"""Exploration benchmark: the demo office explored with no one driving.

Prints one JSON line with:

- ``explore_coverage``: the free area mapped when the ``explore`` goal succeeds / the free
  area the robot could reach (the world's free cells connected to the start), >= 0.95 wanted,
  the built map first put in the world's frame by matching its walls to the world's
  (``explore_map_offset``: x, y, theta of that transform; ``explore_coverage_unaligned``
  without it);
- ``explore_sim_s`` / ``explore_wall_s``: sim and wall time of the whole exploration,
  return to the start included; ``explore_goals`` reached and failed;
- the reference, in the same run: the same explorer with the robot put at each goal at once
  and a ray-cast 360-beam laser (no driving, no noise, no mapping delay):
  ``explore_ref_coverage`` and ``explore_ref_goals``, what the frontier rules alone achieve.

The chassis is a process of its own at ``speed:=10``; nav, the explorer and the mapper run
in this process. The mapper is the slam node (services/slam), with the chassis'
``odom_noise:=0.05 range_noise:=0.02``, and the map it saves at the end is measured; with
``--mapper standin`` the stand-in of the tests (tests/integration/standin_slam.py:
the grid from the scans at the simulator's true pose, ``map`` and ``map -> odom`` as the slam
node publishes them), without noise. ``explore_mapper`` says which. bench/slam.py may take
these keys through its ``FIGURES`` hook (`figures`).

Run: ``python bench/explore.py [--mapper standin]``.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from zenros.action import ActionClient, GoalStatus
from zenros.context import Context
from zenros.maps import GridMap, load_map
from zenros.msgs.zenros_msgs.slam import (
    Explore,
    ExploreGoal,
    SaveSlamMap,
    SaveSlamMapRequest,
    SetMappingMode,
    SetMappingModeRequest,
    StartMapping,
    StartMappingRequest,
)
from zenros.node import Node
from zenros.se2 import Pose2
from zenros.services.explore.explorer import ExploreParams, Explorer
from zenros.services.explore.node import ExploreNode
from zenros.services.nav.node import NavNode
from zenros.services.nav.params import DEMO_MAP
from zenros.services.slam.node import SlamNode
from zenros.testing import Proc, free_port, loopback_options, unique_prefix, wait_for

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).parents[1] / "tests" / "integration"))
from _harness import emit
from standin_slam import TruthMapper, align, coverage, reachable_free

SPEED = 10.0


def reference(world: GridMap, reach: np.ndarray) -> tuple[float, int]:
    """The explorer with the robot teleported to each goal and a ray-cast laser."""
    g, res = world.grid, world.resolution
    seen = np.zeros(g.shape, dtype=bool)
    pose = Pose2(0.0, 0.0, 0.0)
    ex = Explorer(ExploreParams(), pose)
    steps = np.arange(0.0, 12.0, res / 2)
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    built = world
    for t in range(500):
        xs = pose.x + np.outer(np.cos(angles), steps)
        ys = pose.y + np.outer(np.sin(angles), steps)
        cols = np.floor((xs - world.origin[0]) / res).astype(int).clip(0, world.width - 1)
        rows = np.floor((ys - world.origin[1]) / res).astype(int).clip(0, world.height - 1)
        blocked = np.cumsum(g[rows, cols] >= 65, axis=1)
        # a ray sees up to and including its first occupied cell
        visible = (blocked == 0) | ((blocked == 1) & (g[rows, cols] >= 65))
        seen[rows[visible], cols[visible]] = True
        built = GridMap(np.where(seen, g, -1).astype(np.int8), res, world.origin)
        d = ex.step(built, pose, float(t))
        if d.action == "wait":
            continue
        if d.action == "done" or d.target is None:
            break
        pose = d.target
        if d.action == "home":
            ex.returned(True)
        else:
            ex.reached(d.target)
    return coverage(world, built, reach), ex.goals_reached


def explore(world: GridMap, reach: np.ndarray, use_slam: bool) -> dict[str, Any]:
    port, prefix = free_port(), unique_prefix()
    noise = ["-p", "odom_noise:=0.05", "-p", "range_noise:=0.02"] if use_slam else []
    chassis = Proc([sys.executable, "-m", "zenros.services.chassis", "-l",
                    f"tcp/127.0.0.1:{port}", "--prefix", prefix,
                    "-p", f"speed:={SPEED}", "-p", "seed:=1", *noise, "--log-level", "warn"])
    ctx = Context(loopback_options(connect=[port]), prefix=prefix)
    home = tempfile.TemporaryDirectory()
    nodes: list[Node] = []
    try:
        nav = NavNode("nav", context=ctx, parameter_overrides={
            "use_sim_time": True, "maps_dir": home.name})
        nodes.append(nav)
        nodes.append(ExploreNode("explore", context=ctx, parameter_overrides={
            "use_sim_time": True}))
        user = Node("bench_user", context=ctx)
        nodes.append(user)
        client = ActionClient(user, Explore, "explore")
        mode = user.create_client(SetMappingMode, "nav/set_mapping_mode")
        assert client.wait_for_server(20) and mode.wait_for_service(20)
        assert wait_for(lambda: nav.core.localizer.pose() is not None, 30)
        if use_slam:
            nodes.append(SlamNode("slam", context=ctx, parameter_overrides={
                "use_sim_time": True, "graph_dir": home.name}))
            start = user.create_client(StartMapping, "slam/start")
            assert start.wait_for_service(20)
            res = start.call(StartMappingRequest(mode="explore"), timeout=20)
            assert res.code == 0, res.message
        else:
            assert mode.call(SetMappingModeRequest(enable=True), timeout=10).code == 0
            mapper = TruthMapper(user, world, period=1.0)
            mapper.start()
            assert wait_for(lambda: mapper.published > 0, 30)
        sim0, wall0 = nav.now().to_sec(), time.monotonic()
        out = client.send_goal(ExploreGoal(), timeout=1800)
        sim, wall = nav.now().to_sec() - sim0, time.monotonic() - wall0
        assert out.status is GoalStatus.SUCCEEDED, out.result
        if use_slam:  # the map the robot built, as saved (its frame: the start pose)
            save = user.create_client(SaveSlamMap, "slam/save")
            res = save.call(SaveSlamMapRequest(name="explored"), timeout=30)
            assert res.code == 0, res.message
            built = nav.core.maps.store.load("explored")
        else:
            built = mapper.grid()
        assert built is not None
        at = align(world, built)
        return {"coverage": coverage(world, built, reach, at), "sim": sim, "wall": wall,
                "unaligned": coverage(world, built, reach), "offset": at,
                "reached": out.result.goals_reached, "failed": out.result.goals_failed,
                "mapper": "slam (odom_noise 0.05, range_noise 0.02)" if use_slam
                else "standin (truth, no noise)"}
    finally:
        for n in reversed(nodes):
            n.close()
        ctx.close()
        chassis.stop()
        home.cleanup()


def figures(args: object = None) -> dict[str, object]:
    """The exploration keys, for this script's line or another bench's (bench/slam.py's
    ``FIGURES`` hook takes a callable of its parsed arguments)."""
    world = load_map(DEMO_MAP)
    reach = reachable_free(world, (0.0, 0.0))
    ref_cov, ref_goals = reference(world, reach)
    run = explore(world, reach, use_slam=getattr(args, "mapper", "slam") != "standin")
    return {
        "explore_coverage": round(run["coverage"], 3),
        "explore_coverage_unaligned": round(run["unaligned"], 3),
        "explore_map_offset": [round(v, 3) for v in run["offset"]],
        "explore_sim_s": round(run["sim"], 1),
        "explore_wall_s": round(run["wall"], 1),
        "explore_goals": run["reached"],
        "explore_goals_failed": run["failed"],
        "explore_ref_coverage": round(ref_cov, 3),
        "explore_ref_goals": ref_goals,
        "explore_mapper": run["mapper"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mapper", choices=("slam", "standin"), default="slam",
                    help="the slam node (with the chassis' noise) or the tests' stand-in")
    logging.basicConfig(level=logging.WARNING)
    emit("explore", figures(ap.parse_args()), speed=SPEED)


if __name__ == "__main__":
    main()
