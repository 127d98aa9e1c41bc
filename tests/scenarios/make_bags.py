"""Make the scenario bags of tests/integration/test_replay_scenarios.py (docs/replay.md).

A small room (tests/scenarios/maps/room) and a closed-loop simulation run in a
deterministic run with nav: a unicycle integrates nav's ``cmd_vel``; odometry and ground
truth go to nav at 20 Hz and a 180-beam scan, cast against the room and a box the map does
not show, at 10 Hz; a goal comes at 1 s. Every message nav gets is written to the input
bag (log time = simulated time), then ``zenros replay`` of that bag writes the expected
output. Scenarios: ``goal_around_obstacle`` (a goal behind the box) and ``patrol`` (one
loop of the room's path ``patrol``, two nav points).

    .venv/bin/python tests/scenarios/make_bags.py          # rewrites the files here
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np
from zenros.maps import GridMap, load_map, save_map
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import PoseStamped, Twist
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.zenros_msgs.nav import NavPoint, PatrolGoal
from zenros.replay import DeterministicRun
from zenros.replay.bagrun import replay_bag
from zenros.replay.nodes import replayable
from zenros.replay.outbag import OutputBag
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.obstacles import Obstacle
from zenros.services.chassis.world import World
from zenros.services.nav.maps.navdata import MapNavData, StoredPath, write_nav_data
from zenros.services.nav.node import NavNode

HERE = Path(__file__).resolve().parent
RES = 0.05
START_NS = 1_000_000_000  # the run starts at 1 s of simulated time
STEP_NS = 50_000_000  # 20 Hz: odometry and ground truth; the scan every other step
LASER = LaserConfig(beams=180, range_max=8.0)
BOX = Obstacle(id="box", shape="box", x=2.5, y=1.5, size_x=0.5, size_y=0.8)
PATROL = [NavPoint(name="a", x=4.5, y=3.0), NavPoint(name="b", x=1.0, y=0.5, theta=math.pi)]
SCENARIOS: dict[str, dict[str, Any]] = {
    "goal_around_obstacle": {"seconds": 20.0, "box": True,
                             "goal": ("/goal_pose", (5.5, 1.5, 0.0))},
    "patrol": {"seconds": 26.0, "box": False,
               "goal": ("/patrol_goal", PatrolGoal(map_name="room", path_name="patrol",
                                                   loops=1))},
}


def room_map(maps: Path) -> Path:
    """An 8 m x 5 m room (x -1..7, y -1..4) with a pillar, and its nav points; the map
    store folder layout nav reads (``maps/room/room.yaml``). Returns the YAML."""
    g = np.zeros((100, 160), dtype=np.int8)

    def wall(x0: float, y0: float, x1: float, y1: float) -> None:
        g[round((y0 + 1) / RES):round((y1 + 1) / RES), round((x0 + 1) / RES):round((x1 + 1) / RES)] = 100

    wall(-1, -1, 7, -0.9)
    wall(-1, 3.9, 7, 4)
    wall(-1, -1, -0.9, 4)
    wall(6.9, -1, 7, 4)
    wall(3.3, 3.0, 3.7, 4)  # a pillar from the north wall
    folder = maps / "room"
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "room.yaml"
    save_map(GridMap(g, RES, (-1.0, -1.0, 0.0)), path)
    write_nav_data(folder / "nav.yaml",
                   MapNavData(paths={"patrol": StoredPath(nav_points=list(PATROL))}))
    return path


def nav_params(maps: Path) -> dict[str, Any]:
    return {"maps_dir": str(maps), "map": str(maps / "room" / "room.yaml")}


class Robot:
    """A unicycle at (x, y, theta) that follows the last command."""

    def __init__(self) -> None:
        self.x, self.y, self.theta = 0.0, 1.5, 0.0
        self.v = self.w = 0.0

    def command(self, msg: Twist) -> None:
        self.v, self.w = float(msg.linear.x), float(msg.angular.z)

    def step(self, dt: float) -> None:
        self.theta = math.atan2(math.sin(self.theta + self.w * dt),
                                math.cos(self.theta + self.w * dt))
        self.x += self.v * dt * math.cos(self.theta)
        self.y += self.v * dt * math.sin(self.theta)


def odometry(r: Robot, t: int, frame: str) -> Odometry:
    m = Odometry()
    m.header.stamp, m.header.frame_id, m.child_frame_id = Time.from_nanoseconds(t), frame, "base_link"
    m.pose.pose.position.x, m.pose.pose.position.y = r.x, r.y
    m.pose.pose.orientation.z = math.sin(r.theta / 2)
    m.pose.pose.orientation.w = math.cos(r.theta / 2)
    m.twist.twist.linear.x, m.twist.twist.angular.z = r.v, r.w
    return m


def scan(laser: Laser, r: Robot, t: int) -> LaserScan:
    ranges = laser.ranges(r.x, r.y, r.theta).astype(np.float32)
    m = LaserScan(angle_min=LASER.angle_min, angle_max=LASER.angle_max,
                  angle_increment=LASER.angle_increment, scan_time=0.1,
                  range_min=LASER.range_min, range_max=LASER.range_max, ranges=ranges)
    m.header.stamp, m.header.frame_id = Time.from_nanoseconds(t), "base_link"
    return m


def goal_message(goal: Any) -> Any:
    if isinstance(goal, tuple):
        g = PoseStamped()
        g.header.frame_id = "map"
        g.pose.position.x, g.pose.position.y = goal[0], goal[1]
        g.pose.orientation.z, g.pose.orientation.w = math.sin(goal[2] / 2), math.cos(goal[2] / 2)
        return g
    return goal


def simulate(name: str, maps: Path, out: Path, spec: dict[str, Any] | None = None) -> Robot:
    """Run scenario ``name`` (or ``spec``: seconds, box, goal) closed-loop; write nav's
    inputs to ``out``."""
    spec = spec or SCENARIOS[name]
    world = World(load_map(maps / "room" / "room.yaml"))
    if spec["box"]:
        world.set_obstacles([BOX])
    laser = Laser(world, LASER)
    robot = Robot()
    bag = OutputBag(out)

    def on_output(topic: str, msg: Any, t: int) -> None:
        if topic == "/cmd_vel":
            robot.command(msg)

    run = DeterministicRun(START_NS, on_output, exempt=replayable("nav").exempt)
    run.add_node(NavNode, parameter_overrides=nav_params(maps))

    def feed(topic: str, msg: Any, t: int, qos: str = "be+10") -> None:
        bag.add(topic, msg, t, qos)
        run.deliver(topic, msg, t)

    t = START_NS
    steps = int(spec["seconds"] * 1e9 / STEP_NS)
    try:
        for i in range(steps):
            t += STEP_NS
            run.advance_to(t)
            robot.step(STEP_NS / 1e9)
            feed("/odom", odometry(robot, t, "odom"), t)
            feed("/sim/ground_truth", odometry(robot, t, "map"), t)
            if i % 2 == 0:
                feed("/scan", scan(laser, robot, t), t)
            if i == 20:
                topic, goal = spec["goal"]
                feed(topic, goal_message(goal), t, "rel+10")
    finally:
        run.close()
        bag.close()
    return robot


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE, help="where to write (default: here)")
    args = ap.parse_args(argv)
    maps = args.out / "maps"
    room_map(maps)
    for name in SCENARIOS:
        inp = args.out / f"{name}.in.mcap"
        robot = simulate(name, maps, inp)
        expected = args.out / f"{name}.expected.mcap"
        replay_bag(inp, ["nav"], expected, params={"nav": nav_params(maps)})
        print(f"{name}: robot ends at ({robot.x:.2f}, {robot.y:.2f}, {robot.theta:.2f}); "
              f"{inp.stat().st_size // 1024} KB in, {expected.stat().st_size // 1024} KB out")
    return 0


if __name__ == "__main__":
    sys.exit(main())
