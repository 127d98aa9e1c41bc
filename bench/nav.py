"""Navigation benchmark: the controller's achieved rate at 10x sim time, and one RPP step.

Prints one JSON line with:

- ``controller_hz``: control ticks per second of sim time the nav node achieves while it
  drives the simulated robot across the demo office and back (the chassis a process of
  its own at ``speed:=10``, nav in this process), next to ``controller_hz_requested``
  (its ``controller_frequency``, 20) as the reference: ``tick_ratio`` = achieved ÷
  requested (1.0: it keeps up).
- ``wall_hz``: the same ticks per wall second (at 10x, 200 when it keeps up).
- ``goal_sim_s`` / ``goal_wall_s``: the two legs' sim and wall time; ``rtf`` their ratio.
- ``step_us``: one control step in this process, median over a run along an office plan:
  Regulated Pure Pursuit plus the arc collision check against a 360-beam scan's points;
  ``step_hz`` = 1e6 / step_us (Nav2's RPP README: "well over 1 kHz").

Run: ``python bench/nav.py``.
"""

from __future__ import annotations

import logging
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from zenros.action import ActionClient, GoalStatus
from zenros.context import Context
from zenros.maps import load_map
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal
from zenros.node import Node
from zenros.se2 import Pose2
from zenros.services.nav.actions.convert import pose_stamped
from zenros.services.nav.core import NavConfig
from zenros.services.nav.costmap.live import Costmaps
from zenros.services.nav.motion.collision import first_collision
from zenros.services.nav.motion.controller import PurePursuit
from zenros.services.nav.node import NavNode
from zenros.services.nav.params import DEMO_MAP
from zenros.services.nav.planning import PlannerParams
from zenros.services.nav.planning.global_planner import GlobalPlanner
from zenros.testing import Proc, free_port, loopback_options, unique_prefix, wait_for

sys.path.insert(0, str(Path(__file__).parent))
from _harness import emit

SPEED = 10.0


def step_us() -> float:
    """Median microseconds of one controller step along a plan across the office."""
    cfg = NavConfig()
    cm = Costmaps(cfg.costmap)
    cm.set_map(load_map(DEMO_MAP))
    out = GlobalPlanner(PlannerParams(), 0.22).plan(cm.snapshot(), Pose2(0, 0, 0),
                                                      [Pose2(22.0, -5.0, 0.0)])
    assert out.xy is not None
    pp = PurePursuit(cfg.controller)
    pp.set_path(out.xy, 0.0)
    a = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    scan = np.column_stack([1.2 * np.cos(a), 1.25 * np.sin(a)])  # a corridor-like ring
    pose, times, dt = Pose2(0, 0, 0), [], 0.05
    for _ in range(3000):
        t0 = time.perf_counter()
        c = pp.compute(pose, dt, cm.cost_at(pose.x, pose.y))
        first_collision(c.v, c.w, scan, 0.24, 1.0)
        times.append(time.perf_counter() - t0)
        if c.state == "goal_reached":
            break
        th = pose.theta + c.w * dt / 2
        pose = Pose2(pose.x + c.v * dt * math.cos(th), pose.y + c.v * dt * math.sin(th),
                     pose.theta + c.w * dt)
    return statistics.median(times) * 1e6


def drive() -> dict[str, float]:
    port, prefix = free_port(), unique_prefix()
    chassis = Proc([sys.executable, "-m", "zenros.services.chassis", "-l",
                    f"tcp/127.0.0.1:{port}", "--prefix", prefix,
                    "-p", f"speed:={SPEED}", "-p", "seed:=1", "--log-level", "warn"])
    ctx = Context(loopback_options(connect=[port]), prefix=prefix)
    home = tempfile.TemporaryDirectory()
    nav = user = None
    try:
        nav = NavNode("nav", context=ctx, parameter_overrides={
            "use_sim_time": True, "maps_dir": home.name})
        user = Node("bench_user", context=ctx)
        client = ActionClient(user, NavigateToPose, "navigate_to_pose")
        assert client.wait_for_server(20)
        assert wait_for(lambda: nav is not None and nav.core.localizer.pose() is not None, 30)
        ticks0, sim0, wall0 = nav.core.motion.ticks, nav.now().to_sec(), time.monotonic()
        for x, y in ((22.0, -5.0), (0.0, 0.0)):
            goal = NavigateToPoseGoal(pose=pose_stamped(Pose2(x, y, 0.0), Time()))
            res = client.send_goal(goal, timeout=120)
            assert res.status is GoalStatus.SUCCEEDED, res.result
        ticks = nav.core.motion.ticks - ticks0
        sim, wall = nav.now().to_sec() - sim0, time.monotonic() - wall0
        return {"controller_hz": ticks / sim, "wall_hz": ticks / wall, "goal_sim_s": sim,
                "goal_wall_s": wall, "rtf": sim / wall}
    finally:
        for n in (user, nav):
            if n is not None:
                n.close()
        ctx.close()
        chassis.stop()
        home.cleanup()


def main() -> None:
    logging.basicConfig(level=logging.WARNING)
    us = step_us()
    run = drive()
    requested = 20.0
    emit("nav", {
        "controller_hz": round(run["controller_hz"], 2),
        "controller_hz_requested": requested,
        "tick_ratio": round(run["controller_hz"] / requested, 3),
        "wall_hz": round(run["wall_hz"], 1),
        "goal_sim_s": round(run["goal_sim_s"], 1),
        "goal_wall_s": round(run["goal_wall_s"], 2),
        "rtf": round(run["rtf"], 2),
        "step_us": round(us, 1),
        "step_hz": round(1e6 / us),
    }, speed=SPEED)


if __name__ == "__main__":
    main()
