"""ChassisConfig: the chassis parameters, declared on the node, checked, and built into a
`Simulation`."""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np
from zenros.errors import InvalidParameterValueError
from zenros.maps import load_map, load_poses

from .battery import Battery, BatteryConfig
from .dock import Dock
from .drive import Drive, DriveLimits
from .kinematics import Pose2
from .laser import Laser, LaserConfig
from .odometry import Odometry
from .sim import Simulation, start_pose
from .world import World

__all__ = ["DEMO_MAP", "ChassisConfig", "declare_config"]

DEMO_MAP = Path(__file__).resolve().parents[2] / "deploy" / "maps" / "office" / "office.yaml"


class _Declares(Protocol):
    def declare_parameter(self, name: str, default: object, *, description: str = "",
                          read_only: bool = False) -> object: ...


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


def _pose(name: str, value: object) -> Pose2 | None:
    if value in ([], None):
        return None
    if (not isinstance(value, list) or len(value) not in (2, 3)
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                       and math.isfinite(v) for v in value)):
        raise InvalidParameterValueError(
            f"parameter {name!r}: expected [x, y] or [x, y, theta] (finite numbers), got {value!r}")
    return Pose2(*(float(v) for v in value)) if len(value) == 3 else Pose2(
        float(value[0]), float(value[1]), 0.0)


def declare_config(node: _Declares) -> ChassisConfig:
    """Declare every chassis parameter on ``node`` and return them checked.

    Raises:
        InvalidParameterValueError: a value out of range (names the parameter).
    """
    def p(name: str, default: object, description: str = "") -> object:
        return node.declare_parameter(name, default, description=description, read_only=True)

    def f(name: str, default: float, description: str = "", *, positive: bool = False,
          nonneg: bool = True) -> float:
        v = float(p(name, float(default), description))  # type: ignore[arg-type]
        if not math.isfinite(v) or (positive and v <= 0) or (nonneg and v < 0):
            want = " > 0" if positive else " >= 0" if nonneg else ""
            raise InvalidParameterValueError(
                f"parameter {name!r}: expected a finite number{want}, got {v}")
        return v

    map_path = str(p("map", "", "map_server YAML of the world (default: the demo office)"))
    speed = f("speed", 1.0, "sim seconds per wall second; 0 = as fast as possible")
    range_min, range_max = f("range_min", 0.05), f("range_max", 12.0, positive=True)
    if range_min >= range_max:
        raise InvalidParameterValueError(
            f"parameters 'range_min' ({range_min:g}) and 'range_max' ({range_max:g}): "
            "range_min must be below range_max")
    publish_clock = bool(p("publish_clock", True, "publish /clock and stamp with sim time"))
    if not publish_clock and speed != 1.0:
        raise InvalidParameterValueError(
            f"parameter 'speed' is {speed:g} but publish_clock is false: without /clock other "
            "nodes cannot follow a sim that runs faster or slower than real time")
    rate = f("rate", 50.0, "physics steps (and odom, TF) per sim second", positive=True)
    scan_rate = f("scan_rate", 10.0, "scans per sim second", positive=True)
    try:
        limits = DriveLimits(
            max_linear=f("max_linear_velocity", 1.0), max_reverse=f("max_reverse_velocity", 0.3),
            max_angular=f("max_angular_velocity", 1.5),
            max_linear_accel=f("max_linear_acceleration", 1.0),
            max_linear_decel=f("max_linear_deceleration", 2.0),
            max_angular_accel=f("max_angular_acceleration", 3.0),
            cmd_timeout=f("cmd_timeout", 0.5, "dead-man: stop after this long without cmd_vel"))
        laser = LaserConfig(
            beams=int(p("scan_beams", 360)), range_min=range_min,  # type: ignore[call-overload]
            range_max=range_max, fov=f("scan_fov", 2 * math.pi),
            noise=f("range_noise", 0.0, "std dev of laser range noise (m)"))
        battery = BatteryConfig(
            capacity=f("battery_capacity", 20.0), voltage=f("battery_voltage", 24.0),
            idle_current=f("battery_idle_current", 2.0),
            motion_current=f("battery_motion_current", 6.0),
            turn_current=f("battery_turn_current", 2.0),
            charge_current=f("battery_charge_current", 10.0),
            initial=f("battery_initial", 0.9, "state of charge at start, 0..1"))
    except ValueError as exc:
        raise InvalidParameterValueError(str(exc)) from exc
    radius = f("robot_radius", 0.2, "the round body's radius (m)", positive=True)
    odom_noise = f("odom_noise", 0.0, "relative std dev of the odometry's speeds")
    return ChassisConfig(
        map_path=Path(map_path) if map_path else DEMO_MAP,
        speed=speed, publish_clock=publish_clock,
        publish_tf=bool(p("publish_tf", True, "publish odom -> base_link on /tf")),
        rate=rate, scan_rate=scan_rate, robot_radius=radius, limits=limits, laser=laser,
        laser_mount=Pose2(f("laser_x", 0.1, nonneg=False), f("laser_y", 0.0, nonneg=False),
                          f("laser_yaw", 0.0, nonneg=False)),
        laser_z=f("laser_z", 0.2, nonneg=False), battery=battery, odom_noise=odom_noise,
        start=_pose("start_pose", p("start_pose", [], "[x, y, theta] in map; [] = the map's")),
        dock=_pose("dock_pose", p("dock_pose", [], "[x, y, theta] in map; [] = the map's")),
        dock_tolerance=f("dock_tolerance", 0.05), dock_yaw_tolerance=f("dock_yaw_tolerance", 0.1),
        seed=int(p("seed", 0, "random seed for noise; 0 = random")),  # type: ignore[call-overload]
        map_frame=str(p("map_frame", "map")), odom_frame=str(p("odom_frame", "odom")),
        base_frame=str(p("base_frame", "base_link")), laser_frame=str(p("laser_frame", "laser")),
    )
