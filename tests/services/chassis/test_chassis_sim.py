"""Simulation: collision stop with the bumper, odometry, docking and charging, teleport, start."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import pytest
from zenros.maps import GridMap, MapPoses
from zenros.msgs.zenros_msgs import Obstacle as ObstacleMsg
from zenros.msgs.zenros_msgs import SetObstaclesRequest
from zenros.se2 import Pose2
from zenros.services.chassis.device import Chassis, Frames
from zenros.services.chassis.devices import BatteryDevice, DockDevice, LaserDevice, OdometryDevice
from zenros.services.chassis.devices.battery import BatteryParameters
from zenros.services.chassis.devices.dock import DockParameters
from zenros.services.chassis.devices.laser import LaserParameters
from zenros.services.chassis.devices.odometry import OdometryParameters
from zenros.services.chassis.drive import Drive, DriveLimits
from zenros.services.chassis.obstacle_requests import apply_request
from zenros.services.chassis.obstacles import Obstacle
from zenros.services.chassis.pacer import Pacer
from zenros.services.chassis.sim import Simulation, start_pose
from zenros.services.chassis.world import World

DT = 0.02


class Rig:
    """A chassis with odometry, a dock, a battery and an 8-beam laser, and its devices."""

    def __init__(self, world: World, at: Pose2, dock: Pose2 | None, noise: float,
                 battery: BatteryParameters) -> None:
        self.sim = Simulation(world=world, drive=Drive(DriveLimits(cmd_timeout=100.0)),
                              truth=at, radius=0.2)
        self.chassis = Chassis(sim=self.sim, frames=Frames(), step_rate=1 / DT,
                               rng=np.random.default_rng(2), poses=MapPoses(),
                               map_path=Path("test.yaml"), pacer=Pacer(DT, 1.0),
                               logger=logging.getLogger("test"))
        dock_pose = [] if dock is None else [dock.x, dock.y, dock.theta]
        self.odometry = self.chassis.fit(OdometryDevice, OdometryParameters(odom_noise=noise))
        self.dock = self.chassis.fit(DockDevice, DockParameters(dock_pose=dock_pose))
        self.battery = self.chassis.fit(BatteryDevice, battery).battery
        self.laser = self.chassis.fit(LaserDevice, LaserParameters(scan_beams=8))

    @property
    def truth(self) -> Pose2:
        return self.sim.truth

    @property
    def bumper(self) -> bool:
        return self.sim.bumper

    @property
    def docked(self) -> bool:
        return self.dock.docked

    def scan(self) -> np.ndarray:
        return self.laser.ranges()


def make_sim(world: World, at: Pose2 = Pose2(1.0, 1.5, 0.0), *, dock: Pose2 | None = None,
             noise: float = 0.0, battery: BatteryParameters | None = None) -> Rig:
    return Rig(world, at, dock, noise, battery or BatteryParameters())


def run(rig: Rig, v: float, w: float, seconds: float) -> None:
    for _ in range(round(seconds / DT)):
        rig.sim.drive.command(v, w, rig.sim.time)
        rig.chassis.step(DT)


def test_drives_and_odometry_matches_truth_without_noise(room: World) -> None:
    rig = make_sim(room)
    run(rig, 0.5, 0.3, 3.0)
    assert not rig.bumper and rig.truth.x > 1.8
    assert rig.odometry.odom_in_map == pytest.approx(Pose2(1.0, 1.5, 0.0), abs=1e-9)
    assert rig.odometry.odometry.linear == pytest.approx(0.5)


def test_odometry_noise_drifts(room: World) -> None:
    rig = make_sim(room, noise=0.05)
    run(rig, 0.5, 0.3, 3.0)
    assert rig.odometry.odom_in_map != pytest.approx(Pose2(1.0, 1.5, 0.0), abs=1e-4)
    assert rig.odometry.odometry.pose_covariance()[0] > 0.001


def test_stops_at_the_wall_with_the_bumper_and_never_enters_it(room: World) -> None:
    rig = make_sim(room)
    run(rig, 1.0, 0.0, 6.0)  # the east wall's face is at x = 4.95
    assert rig.bumper and rig.sim.drive.linear == 0.0
    assert 4.95 - 0.2 - 0.005 < rig.truth.x <= 4.95 - 0.2
    x = rig.truth.x
    run(rig, 1.0, 0.0, 1.0)  # pushing on: stays put
    assert rig.truth.x == pytest.approx(x) and rig.bumper
    run(rig, -0.3, 0.0, 0.5)  # backing off releases the bumper
    assert not rig.bumper and rig.truth.x < x
    assert rig.scan()[4] == pytest.approx(4.95 - rig.truth.x - 0.1, abs=1e-4)


def test_obstacles_block_the_body_and_requests_are_checked(room: World) -> None:
    rig = make_sim(room)
    box = ObstacleMsg(id="crate", shape="box", x=2.5, y=1.5, size_x=0.4, size_y=1.0)
    assert apply_request(rig.sim, SetObstaclesRequest(obstacles=[box])) == ""
    run(rig, 1.0, 0.0, 3.0)
    assert rig.bumper and 2.3 - 0.2 - 0.005 < rig.truth.x <= 2.3 - 0.2
    on_robot = ObstacleMsg(id="x", shape="circle", x=rig.truth.x, y=1.5, radius=0.1)
    assert "overlap the robot" in apply_request(rig.sim, SetObstaclesRequest(obstacles=[on_robot]))
    bad = ObstacleMsg(id="y", shape="circle", x=1.0, y=1.0, radius=-1.0)
    assert "radius > 0" in apply_request(rig.sim, SetObstaclesRequest(obstacles=[bad]))
    assert "unknown obstacle ids ['nope']" in apply_request(
        rig.sim, SetObstaclesRequest(op="remove", ids=["nope"]))
    moved = ObstacleMsg(id="crate", shape="circle", x=4.0, y=0.5, radius=0.3)
    assert apply_request(rig.sim, SetObstaclesRequest(obstacles=[moved])) == ""
    assert rig.sim.world.obstacles["crate"].shape == "circle"
    assert apply_request(rig.sim, SetObstaclesRequest(op="replace", obstacles=[box])) == ""
    assert apply_request(rig.sim, SetObstaclesRequest(op="clear")) == ""
    assert rig.sim.world.obstacles == {}
    run(rig, 1.0, 0.0, 3.0)
    assert rig.truth.x > 4.0


def test_driving_onto_the_dock_charges() -> None:
    grid = np.zeros((60, 100), np.int8)
    grid[:, -1] = 100
    grid[25:35, 90:] = 100  # the dock block, face at x = 4.5
    world = World(GridMap(grid, 0.05, (0.0, 0.0, 0.0)))
    dock = Pose2(4.5 - 0.22, 1.5, 0.0)
    rig = make_sim(world, Pose2(3.0, 1.5, 0.0), dock=dock,
                   battery=BatteryParameters(battery_initial=0.5, battery_charge_current=10.0))
    run(rig, 0.3, 0.0, 8.0)
    assert rig.bumper and rig.docked and rig.battery.charging
    p = rig.battery.percentage
    run(rig, 0.0, 0.0, 60.0)
    assert rig.battery.percentage > p
    run(rig, -0.3, 0.0, 1.0)
    assert not rig.docked and not rig.battery.charging


def test_empty_battery_stops_the_base(room: World) -> None:
    rig = make_sim(room, battery=BatteryParameters(battery_capacity=0.001, battery_initial=0.01))
    run(rig, 0.5, 0.0, 1.0)
    assert rig.battery.empty
    x = rig.truth.x
    run(rig, 0.5, 0.0, 1.0)
    assert rig.truth.x == x


def test_teleport(room: World) -> None:
    rig = make_sim(room)
    assert rig.sim.teleport(Pose2(3.0, 2.0, 7.0)) == ""
    assert rig.truth == pytest.approx(Pose2(3.0, 2.0, 7.0 - 2 * math.pi))
    assert "outside the map" in rig.sim.teleport(Pose2(30.0, 2.0, 0.0))
    assert "does not fit" in rig.sim.teleport(Pose2(0.1, 2.0, 0.0))
    assert "finite" in rig.sim.teleport(Pose2(math.nan, 2.0, 0.0))
    room.set_obstacles([Obstacle("c", "circle", 2.0, 1.0, radius=0.3)])
    assert "does not fit" in rig.sim.teleport(Pose2(2.0, 1.45, 0.0))


def test_start_pose_rules(room: World) -> None:
    assert start_pose(room, 0.2, Pose2(1.0, 1.0, 0.5)) == Pose2(1.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="does not fit"):
        start_pose(room, 0.2, Pose2(0.1, 1.0, 0.0))
    # no start pose: (0, 0) is in the wall corner here, so the nearest free place
    p = start_pose(room, 0.2, None)
    assert room.body_free(p.x, p.y, 0.2) and math.hypot(p.x, p.y) < 0.4 < math.hypot(p.x, p.y) + 0.1
    free = World(GridMap(np.zeros((40, 40), np.int8), 0.05, (-1.0, -1.0, 0.0)))
    assert start_pose(free, 0.2, None) == Pose2(0.0, 0.0, 0.0)
