"""Behaviours driven tick by tick on a simulated unicycle (no network): Navigate reaches a
goal, fails fast on an occupied goal, recovers then gives up when blocked; Motion preempts;
Dock reaches the dock and waits for charge; Patrol loops; AutoCharge decides."""

from __future__ import annotations

import math

import numpy as np
from zenros.maps import GridMap
from zenros.msgs.nav2_msgs import ComputePathToPoseResult as PlanCodes
from zenros.msgs.nav2_msgs import DockRobotResult, FollowPathResult
from zenros.se2 import Pose2
from zenros.services.nav.costmap import CostmapParams
from zenros.services.nav.costmap.live import Costmaps
from zenros.services.nav.motion.active import Motion
from zenros.services.nav.motion.autocharge import AutoCharge
from zenros.services.nav.motion.behavior import Behavior, NavParams, Sense
from zenros.services.nav.motion.collision import points_in_frame
from zenros.services.nav.motion.controller import ControllerParams
from zenros.services.nav.motion.docking import Dock, DockParams, Undock
from zenros.services.nav.motion.navigate import Navigate
from zenros.services.nav.motion.patrol import Patrol
from zenros.services.nav.planning import PlannerParams
from zenros.services.nav.planning.global_planner import GlobalPlanner, PlanWorker

DT = 0.05


class Tools:
    """NavTools over a walled 10 m x 6 m room with a wall at x = 5 (door at y 4..5)."""

    def __init__(self) -> None:
        g = np.zeros((120, 200), dtype=np.int8)
        g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = 100
        g[:, 100] = 100
        g[80:100, 100] = 0
        self.costmaps = Costmaps(CostmapParams(robot_radius=0.2, inflation_radius=0.5,
                                               cost_scaling_factor=3.0))
        self.costmaps.set_map(GridMap(g, 0.05, (0.0, 0.0, 0.0)))
        # synchronous: a plan is ready at the next tick, so no wall-clock wait per tick
        self.worker = PlanWorker(GlobalPlanner(PlannerParams(), 0.2, goal_tolerance=0.05),
                                 self.costmaps.snapshot, threaded=False)
        self.plans: list[np.ndarray] = []
        self.cleared = 0

    def cost_at(self, x: float, y: float) -> int:
        return self.costmaps.cost_at(x, y)

    def keepout_hit(self, points: np.ndarray) -> bool:
        return self.costmaps.keepout_hit(points)

    def clear_obstacles(self) -> None:
        self.cleared += 1

    def on_plan(self, xy: np.ndarray) -> None:
        self.plans.append(xy)


class World:
    """A unicycle that obeys the commands, and its clock."""

    def __init__(self, pose: Pose2, obstacles: np.ndarray | None = None) -> None:
        self.pose, self.t = pose, 0.0
        self.obstacles = obstacles if obstacles is not None else np.zeros((0, 2))
        """Obstacle points fixed in the map frame; the robot senses them in its own."""
        self.charging = False
        self.docked = False
        self.max_travel = 0.0

    def run(self, b: Behavior, seconds: float, wall_wait: float = 0.0) -> None:
        """Tick until the behaviour ends (the Tools' planner is synchronous, so a tick needs
        no wall time; ``wall_wait`` > 0 sleeps that long per tick, as a threaded planner's
        control loop would)."""
        import time

        for _ in range(int(seconds / DT)):
            seen = points_in_frame(self.obstacles, *self.pose)
            v, w = b.step(Sense(now=self.t, dt=DT, pose=self.pose, speed=(0.0, 0.0),
                                obstacles=seen, charging=self.charging,
                                docked=self.docked))
            if b.done.is_set():
                return
            th = self.pose.theta + w * DT / 2
            self.pose = Pose2(self.pose.x + v * DT * math.cos(th),
                              self.pose.y + v * DT * math.sin(th), self.pose.theta + w * DT)
            self.max_travel = max(self.max_travel, abs(v))
            self.t += DT
            if wall_wait:
                time.sleep(wall_wait)


def nav(tools: Tools, goal: Pose2, **kw: object) -> Navigate:
    return Navigate([goal], tools, NavParams(robot_radius=0.2, **kw),  # type: ignore[arg-type]
                    ControllerParams(xy_goal_tolerance=0.1, yaw_goal_tolerance=0.1))


def test_navigate_goes_through_the_door_to_the_goal() -> None:
    tools = Tools()
    try:
        world = World(Pose2(1.0, 1.0, 0.0))
        b = nav(tools, Pose2(8.0, 1.0, math.pi))
        world.run(b, 120)
        assert b.succeeded, b.error_msg
        assert world.pose.distance(Pose2(8.0, 1.0)) <= 0.1
        assert abs(math.remainder(world.pose.theta - math.pi, 2 * math.pi)) <= 0.1
        assert tools.plans and np.max(tools.plans[0][:, 1]) > 4.0
    finally:
        tools.worker.close()


def test_occupied_goal_fails_at_once_with_the_planner_code() -> None:
    tools = Tools()
    try:
        world = World(Pose2(1.0, 1.0, 0.0))
        b = nav(tools, Pose2(5.0, 2.0))
        world.run(b, 10)
        assert b.done.is_set() and not b.succeeded
        assert b.error_code == PlanCodes.GOAL_OCCUPIED
        assert world.max_travel == 0.0 and tools.cleared == 1  # cleared, retried, failed
    finally:
        tools.worker.close()


def test_blocked_robot_recovers_then_gives_up_in_bounded_time() -> None:
    tools = Tools()
    try:
        # boxed in: a ring of obstacle points 0.4 m round the start
        a = np.linspace(-math.pi, math.pi, 72, endpoint=False)
        ring = np.column_stack([1.0 + 0.4 * np.cos(a), 1.0 + 0.4 * np.sin(a)])
        world = World(Pose2(1.0, 1.0, 0.0), obstacles=ring)
        b = nav(tools, Pose2(3.0, 1.0), max_recoveries=3, blocked_wait=0.5,
                wait_duration=0.5)
        world.run(b, 60)
        assert b.done.is_set() and not b.succeeded
        assert b.error_code == FollowPathResult.FAILED_TO_MAKE_PROGRESS
        assert b.recoveries == 3 and world.t < 30
    finally:
        tools.worker.close()


def test_motion_preempts_and_stops_once() -> None:
    motion = Motion()
    changes: list[object] = []
    motion.on_change = changes.append

    class Drive(Behavior):
        def tick(self, sense: Sense) -> tuple[float, float]:
            return 0.3, 0.0

    a, b = Drive(), Drive()
    s = Sense(now=0.0, dt=DT, pose=Pose2())
    assert motion.tick(s) is None
    motion.start(a)
    assert motion.tick(s) == (0.3, 0.0)
    motion.start(b)
    assert a.done.is_set() and a.halted and not a.succeeded and "preempted" in a.error_msg
    assert motion.tick(s) == (0.3, 0.0) and motion.active is b
    assert motion.halt(a) is False  # not the active one
    assert motion.halt(b, "canceled") and b.error_msg == "canceled"
    assert motion.tick(s) == (0.0, 0.0)  # one stop command
    assert motion.tick(s) is None
    assert changes == [a, b, None]


def test_dock_drives_on_and_waits_for_charge() -> None:
    tools = Tools()
    try:
        dock = Pose2(2.0, 3.0, -math.pi / 2)
        world = World(Pose2(1.0, 1.0, 0.0))
        b = Dock(dock, DockParams(wait_charge_timeout=1.0, max_retries=0),
                 lambda goal: nav(tools, goal))
        world.run(b, 80)
        assert b.done.is_set() and not b.succeeded  # nobody charges it
        assert b.error_code == DockRobotResult.FAILED_TO_CHARGE
        assert world.pose.distance(dock) <= 0.05
        world2 = World(Pose2(1.0, 1.0, 0.0))
        b2 = Dock(dock, DockParams(), lambda goal: nav(tools, goal))
        original = world2.run

        def run_charging(beh: Behavior, seconds: float, wall_wait: float = 0.0) -> None:
            world2.charging = False
            original(beh, seconds, wall_wait)

        run_charging(b2, 0.1)
        world2.charging = True  # the chassis reports charging from now on
        world2.pose = dock
        world2.run(b2, 30)
        assert b2.succeeded
        undock = Undock(dock, DockParams(), timeout=30)
        world2.run(undock, 30)
        assert undock.succeeded and world2.pose.distance(dock) >= 0.6
    finally:
        tools.worker.close()


def test_patrol_loops_and_counts() -> None:
    tools = Tools()
    try:
        world = World(Pose2(1.0, 1.0, 0.0))
        b = Patrol([Pose2(2.0, 1.0), Pose2(2.0, 2.0)], lambda g: nav(tools, g), loops=2,
                   wait_time=0.5)
        world.run(b, 120)
        assert b.succeeded and b.loop == 2 and b.visited == 4 and not b.missed
    finally:
        tools.worker.close()


def test_autocharge_decides_once_per_period() -> None:
    ac = AutoCharge(enabled=True, threshold=0.2, retry_period=60.0)
    assert not ac.due(0.5, False, False, False, 0.0)
    assert not ac.due(0.1, True, False, False, 0.0)  # already charging
    assert not ac.due(0.1, False, False, True, 0.0)  # busy
    assert ac.due(0.1, False, False, False, 1.0)
    assert not ac.due(0.1, False, False, False, 30.0)  # tried a moment ago
    assert ac.due(0.1, False, False, False, 62.0)
    assert not AutoCharge(enabled=False).due(0.0, False, False, False, 0.0)
