"""Simulation: collision stop with the bumper, odometry, docking and charging, teleport, start."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.maps import GridMap
from zenros.msgs.zenros_msgs import Obstacle as ObstacleMsg
from zenros.msgs.zenros_msgs import SetObstaclesRequest
from zenros.se2 import Pose2
from zenros.services.chassis.battery import Battery, BatteryConfig
from zenros.services.chassis.dock import Dock
from zenros.services.chassis.drive import Drive, DriveLimits
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.obstacle_requests import apply_request
from zenros.services.chassis.obstacles import Obstacle
from zenros.services.chassis.odometry import Odometry
from zenros.services.chassis.sim import Simulation, start_pose
from zenros.services.chassis.world import World

DT = 0.02


def make_sim(world: World, at: Pose2 = Pose2(1.0, 1.5, 0.0), *, dock: Dock | None = None,
             noise: float = 0.0, battery: BatteryConfig | None = None) -> Simulation:
    return Simulation(world=world, drive=Drive(DriveLimits(cmd_timeout=100.0)),
                      laser=Laser(world, LaserConfig(beams=8)),
                      odometry=Odometry(noise, np.random.default_rng(2)),
                      battery=Battery(battery or BatteryConfig()), dock=dock, truth=at,
                      radius=0.2, laser_mount=Pose2(0.1, 0.0, 0.0))


def run(sim: Simulation, v: float, w: float, seconds: float) -> None:
    for _ in range(round(seconds / DT)):
        sim.drive.command(v, w, sim.time)
        sim.step(DT)


def test_drives_and_odometry_matches_truth_without_noise(room: World) -> None:
    sim = make_sim(room)
    run(sim, 0.5, 0.3, 3.0)
    assert not sim.bumper and sim.truth.x > 1.8
    assert sim.odom_in_map == pytest.approx(Pose2(1.0, 1.5, 0.0), abs=1e-9)
    assert sim.odometry.linear == pytest.approx(0.5)


def test_odometry_noise_drifts(room: World) -> None:
    sim = make_sim(room, noise=0.05)
    run(sim, 0.5, 0.3, 3.0)
    assert sim.odom_in_map != pytest.approx(Pose2(1.0, 1.5, 0.0), abs=1e-4)
    assert sim.odometry.pose_covariance()[0] > 0.001


def test_stops_at_the_wall_with_the_bumper_and_never_enters_it(room: World) -> None:
    sim = make_sim(room)
    run(sim, 1.0, 0.0, 6.0)  # the east wall's face is at x = 4.95
    assert sim.bumper and sim.drive.linear == 0.0
    assert 4.95 - 0.2 - 0.005 < sim.truth.x <= 4.95 - 0.2
    x = sim.truth.x
    run(sim, 1.0, 0.0, 1.0)  # pushing on: stays put
    assert sim.truth.x == pytest.approx(x) and sim.bumper
    run(sim, -0.3, 0.0, 0.5)  # backing off releases the bumper
    assert not sim.bumper and sim.truth.x < x
    assert sim.scan()[4] == pytest.approx(4.95 - sim.truth.x - 0.1, abs=1e-4)


def test_obstacles_block_the_body_and_requests_are_checked(room: World) -> None:
    sim = make_sim(room)
    box = ObstacleMsg(id="crate", shape="box", x=2.5, y=1.5, size_x=0.4, size_y=1.0)
    assert apply_request(sim, SetObstaclesRequest(obstacles=[box])) == ""
    run(sim, 1.0, 0.0, 3.0)
    assert sim.bumper and 2.3 - 0.2 - 0.005 < sim.truth.x <= 2.3 - 0.2
    on_robot = ObstacleMsg(id="x", shape="circle", x=sim.truth.x, y=1.5, radius=0.1)
    assert "overlap the robot" in apply_request(sim, SetObstaclesRequest(obstacles=[on_robot]))
    bad = ObstacleMsg(id="y", shape="circle", x=1.0, y=1.0, radius=-1.0)
    assert "radius > 0" in apply_request(sim, SetObstaclesRequest(obstacles=[bad]))
    assert "unknown obstacle ids ['nope']" in apply_request(
        sim, SetObstaclesRequest(op="remove", ids=["nope"]))
    moved = ObstacleMsg(id="crate", shape="circle", x=4.0, y=0.5, radius=0.3)
    assert apply_request(sim, SetObstaclesRequest(obstacles=[moved])) == ""
    assert sim.world.obstacles["crate"].shape == "circle"
    assert apply_request(sim, SetObstaclesRequest(op="replace", obstacles=[box])) == ""
    assert apply_request(sim, SetObstaclesRequest(op="clear")) == ""
    assert sim.world.obstacles == {}
    run(sim, 1.0, 0.0, 3.0)
    assert sim.truth.x > 4.0


def test_driving_onto_the_dock_charges() -> None:
    grid = np.zeros((60, 100), np.int8)
    grid[:, -1] = 100
    grid[25:35, 90:] = 100  # the dock block, face at x = 4.5
    world = World(GridMap(grid, 0.05, (0.0, 0.0, 0.0)))
    dock = Dock(Pose2(4.5 - 0.22, 1.5, 0.0))
    sim = make_sim(world, Pose2(3.0, 1.5, 0.0), dock=dock,
                   battery=BatteryConfig(initial=0.5, charge_current=10.0))
    run(sim, 0.3, 0.0, 8.0)
    assert sim.bumper and sim.docked and sim.battery.charging
    p = sim.battery.percentage
    run(sim, 0.0, 0.0, 60.0)
    assert sim.battery.percentage > p
    run(sim, -0.3, 0.0, 1.0)
    assert not sim.docked and not sim.battery.charging


def test_empty_battery_stops_the_base(room: World) -> None:
    sim = make_sim(room, battery=BatteryConfig(capacity=0.001, initial=0.01))
    run(sim, 0.5, 0.0, 1.0)
    assert sim.battery.empty
    x = sim.truth.x
    run(sim, 0.5, 0.0, 1.0)
    assert sim.truth.x == x


def test_teleport(room: World) -> None:
    sim = make_sim(room)
    assert sim.teleport(Pose2(3.0, 2.0, 7.0)) == ""
    assert sim.truth == pytest.approx(Pose2(3.0, 2.0, 7.0 - 2 * math.pi))
    assert "outside the map" in sim.teleport(Pose2(30.0, 2.0, 0.0))
    assert "does not fit" in sim.teleport(Pose2(0.1, 2.0, 0.0))
    assert "finite" in sim.teleport(Pose2(math.nan, 2.0, 0.0))
    room.set_obstacles([Obstacle("c", "circle", 2.0, 1.0, radius=0.3)])
    assert "does not fit" in sim.teleport(Pose2(2.0, 1.45, 0.0))


def test_start_pose_rules(room: World) -> None:
    assert start_pose(room, 0.2, Pose2(1.0, 1.0, 0.5)) == Pose2(1.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="does not fit"):
        start_pose(room, 0.2, Pose2(0.1, 1.0, 0.0))
    # no start pose: (0, 0) is in the wall corner here, so the nearest free place
    p = start_pose(room, 0.2, None)
    assert room.body_free(p.x, p.y, 0.2) and math.hypot(p.x, p.y) < 0.4 < math.hypot(p.x, p.y) + 0.1
    free = World(GridMap(np.zeros((40, 40), np.int8), 0.05, (-1.0, -1.0, 0.0)))
    assert start_pose(free, 0.2, None) == Pose2(0.0, 0.0, 0.0)
