"""`ChassisParameters`: the chassis's parameters, their only defaults, limits and descriptions;
`chassis_config` checks their combinations into a `ChassisConfig`, which builds the
`Simulation`."""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import msgspec
import numpy as np
from msgspec import Meta
from zenros.errors import InvalidParameterValueError
from zenros.maps import load_map, load_poses
from zenros.se2 import Pose2

from .battery import Battery, BatteryConfig
from .dock import Dock
from .drive import Drive, DriveLimits
from .laser import Laser, LaserConfig
from .odometry import Odometry
from .sim import Simulation, start_pose
from .world import World

__all__ = ["DEMO_MAP", "ChassisConfig", "ChassisParameters", "chassis_config"]

DEMO_MAP = Path(__file__).resolve().parents[2] / "deploy" / "maps" / "office" / "office.yaml"


Positive = Annotated[float, Meta(gt=0)]
NonNegative = Annotated[float, Meta(ge=0)]
PoseList = Annotated[list[float], Meta(max_length=3,
                                       description="[x, y, theta] in map; [] = the map's")]


class ChassisParameters(msgspec.Struct, kw_only=True):
    """Every chassis parameter (declared read-only: the simulation is built once)."""

    map: Annotated[str, Meta(description="map_server YAML of the world (default: the demo "
                                         "office)")] = ""
    speed: Annotated[NonNegative, Meta(
        description="sim seconds per wall second; 0 = as fast as possible")] = 1.0
    publish_clock: Annotated[bool, Meta(
        description="publish /clock and stamp with sim time")] = True
    publish_tf: Annotated[bool, Meta(description="publish odom -> base_link on /tf")] = True
    rate: Annotated[Positive, Meta(
        description="physics steps (and odom, TF) per sim second")] = 50.0
    scan_rate: Annotated[Positive, Meta(description="scans per sim second")] = 10.0
    max_linear_velocity: NonNegative = 1.0
    max_reverse_velocity: NonNegative = 0.3
    max_angular_velocity: NonNegative = 1.5
    max_linear_acceleration: NonNegative = 1.0
    max_linear_deceleration: NonNegative = 2.0
    max_angular_acceleration: NonNegative = 3.0
    cmd_timeout: Annotated[NonNegative, Meta(
        description="dead-man: stop after this long without cmd_vel")] = 0.5
    scan_beams: int = 360
    range_min: NonNegative = 0.05
    range_max: Positive = 12.0
    scan_fov: NonNegative = 2 * math.pi
    range_noise: Annotated[NonNegative, Meta(
        description="std dev of laser range noise (m)")] = 0.0
    battery_capacity: NonNegative = 20.0
    battery_voltage: NonNegative = 24.0
    battery_idle_current: NonNegative = 2.0
    battery_motion_current: NonNegative = 6.0
    battery_turn_current: NonNegative = 2.0
    battery_charge_current: NonNegative = 10.0
    battery_initial: Annotated[float, Meta(ge=0, le=1,
                                           description="state of charge at start")] = 0.9
    robot_radius: Annotated[Positive, Meta(description="the round body's radius (m)")] = 0.2
    odom_noise: Annotated[NonNegative, Meta(
        description="relative std dev of the odometry's speeds")] = 0.0
    laser_x: float = 0.1
    laser_y: float = 0.0
    laser_yaw: float = 0.0
    laser_z: float = 0.2
    start_pose: PoseList = msgspec.field(default_factory=list)
    dock_pose: PoseList = msgspec.field(default_factory=list)
    dock_tolerance: NonNegative = 0.05
    dock_yaw_tolerance: NonNegative = 0.1
    seed: Annotated[int, Meta(description="random seed for noise; 0 = random")] = 0
    map_frame: str = "map"
    odom_frame: str = "odom"
    base_frame: str = "base_link"
    laser_frame: str = "laser"
    world_topic: Annotated[str, Meta(
        description="a topic the robots of one simulated world share: this chassis publishes "
                    "its body there and sees the others' in its laser and bumper ('' = alone)"
    )] = ""
    world_rate: Annotated[Positive, Meta(
        description="body messages per sim second on world_topic while the robot moves "
                    "(at rest: every 0.5 s)")] = 10.0


@dataclass(frozen=True)
class ChassisConfig:
    """Everything the chassis reads from its parameters (docs/chassis.md lists them)."""

    map_path: Path
    speed: float
    publish_clock: bool
    publish_tf: bool
    rate: float
    scan_rate: float
    robot_radius: float
    limits: DriveLimits
    laser: LaserConfig
    laser_mount: Pose2
    laser_z: float
    battery: BatteryConfig
    odom_noise: float
    start: Pose2 | None
    dock: Pose2 | None
    dock_tolerance: float
    dock_yaw_tolerance: float
    seed: int
    map_frame: str = "map"
    odom_frame: str = "odom"
    base_frame: str = "base_link"
    laser_frame: str = "laser"

    @property
    def odom_every(self) -> int:
        return 1

    @property
    def scan_every(self) -> int:
        return max(1, round(self.rate / self.scan_rate))

    @property
    def state_every(self) -> int:
        return max(1, round(self.rate / 5))

    @property
    def battery_every(self) -> int:
        return max(1, round(self.rate))

    def build(self, logger: logging.Logger) -> Simulation:
        """Load the map and make the simulation (raises ValueError/MapError when it can't)."""
        grid_map = load_map(self.map_path)
        poses = load_poses(self.map_path)
        world = World(grid_map)
        rng = np.random.default_rng(self.seed or None)
        dock = self.dock or (Pose2(*poses.dock) if poses.dock else None)
        start = self.start or (Pose2(*poses.start) if poses.start else None)
        if dock is None:
            logger.warning("no dock pose (parameter dock_pose or %s): the robot cannot charge",
                           self.map_path.parent / "poses.yaml")
        return Simulation(
            world=world, drive=Drive(self.limits),
            laser=Laser(world, self.laser, rng), odometry=Odometry(self.odom_noise, rng),
            battery=Battery(self.battery),
            dock=Dock(dock, self.dock_tolerance, self.dock_yaw_tolerance) if dock else None,
            truth=start_pose(world, self.robot_radius, start), radius=self.robot_radius,
            laser_mount=self.laser_mount,
        )


def _pose(name: str, value: list[float]) -> Pose2 | None:
    if not value:
        return None
    if len(value) not in (2, 3) or not all(math.isfinite(v) for v in value):
        raise InvalidParameterValueError(
            f"parameter {name!r}: expected [x, y] or [x, y, theta] (finite numbers), "
            f"got {value!r}")
    x, y, *theta = value
    return Pose2(x, y, theta[0] if theta else 0.0)


def chassis_config(p: ChassisParameters) -> ChassisConfig:
    """The configuration from the parameters, with their combinations checked.

    Raises:
        InvalidParameterValueError: parameters that do not go together (names them).
    """
    if p.range_min >= p.range_max:
        raise InvalidParameterValueError(
            f"parameters 'range_min' ({p.range_min:g}) and 'range_max' ({p.range_max:g}): "
            "range_min must be below range_max")
    if not p.publish_clock and p.speed != 1.0:
        raise InvalidParameterValueError(
            f"parameter 'speed' is {p.speed:g} but publish_clock is false: without /clock other "
            "nodes cannot follow a sim that runs faster or slower than real time")
    try:
        limits = DriveLimits(
            max_linear=p.max_linear_velocity, max_reverse=p.max_reverse_velocity,
            max_angular=p.max_angular_velocity, max_linear_accel=p.max_linear_acceleration,
            max_linear_decel=p.max_linear_deceleration,
            max_angular_accel=p.max_angular_acceleration, cmd_timeout=p.cmd_timeout)
        laser = LaserConfig(beams=p.scan_beams, range_min=p.range_min, range_max=p.range_max,
                            fov=p.scan_fov, noise=p.range_noise)
        battery = BatteryConfig(
            capacity=p.battery_capacity, voltage=p.battery_voltage,
            idle_current=p.battery_idle_current, motion_current=p.battery_motion_current,
            turn_current=p.battery_turn_current, charge_current=p.battery_charge_current,
            initial=p.battery_initial)
    except ValueError as exc:
        raise InvalidParameterValueError(str(exc)) from exc
    return ChassisConfig(
        map_path=Path(p.map) if p.map else DEMO_MAP,
        speed=p.speed, publish_clock=p.publish_clock, publish_tf=p.publish_tf,
        rate=p.rate, scan_rate=p.scan_rate, robot_radius=p.robot_radius, limits=limits,
        laser=laser, laser_mount=Pose2(p.laser_x, p.laser_y, p.laser_yaw), laser_z=p.laser_z,
        battery=battery, odom_noise=p.odom_noise,
        start=_pose("start_pose", p.start_pose), dock=_pose("dock_pose", p.dock_pose),
        dock_tolerance=p.dock_tolerance, dock_yaw_tolerance=p.dock_yaw_tolerance, seed=p.seed,
        map_frame=p.map_frame, odom_frame=p.odom_frame, base_frame=p.base_frame,
        laser_frame=p.laser_frame,
    )
