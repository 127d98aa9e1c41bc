"""`ChassisParameters`: the body's parameters (world, time, drive); `declare_chassis` declares
them and every device's (`devices.DEVICES`), checks them into a `ChassisConfig`, which
builds the `Chassis`."""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any

import msgspec
import numpy as np
from msgspec import Meta
from zenros.errors import InvalidParameterValueError
from zenros.maps import load_map, load_poses
from zenros.param_config import declare_parameters
from zenros.params import Parameters
from zenros.se2 import Pose2

from .device import Chassis, Device, Frames
from .devices import DEVICES
from .drive import Drive, DriveLimits
from .pacer import Pacer
from .param_types import NonNegative, PoseList, Positive, pose_from
from .sim import Simulation, start_pose
from .world import World

__all__ = ["DEMO_MAP", "ChassisConfig", "ChassisParameters", "chassis_config",
           "declare_chassis", "parameter_structs"]

DEMO_MAP = Path(__file__).resolve().parents[2] / "deploy" / "maps" / "office" / "office.yaml"


class ChassisParameters(msgspec.Struct, kw_only=True):
    """The chassis's own parameters: its world, its time, its body and drive (declared
    read-only: the simulation is built once). Each device has its own Struct."""

    map: Annotated[str, Meta(description="map_server YAML of the world (default: the demo "
                                         "office)")] = ""
    speed: Annotated[NonNegative, Meta(
        description="sim seconds per wall second; 0 = as fast as possible")] = 1.0
    publish_clock: Annotated[bool, Meta(
        description="publish /clock and stamp with sim time")] = True
    rate: Annotated[Positive, Meta(
        description="physics steps (and odom, TF) per sim second")] = 50.0
    max_linear_velocity: NonNegative = 1.0
    max_reverse_velocity: NonNegative = 0.3
    max_angular_velocity: NonNegative = 1.5
    max_linear_acceleration: NonNegative = 1.0
    max_linear_deceleration: NonNegative = 2.0
    max_angular_acceleration: NonNegative = 3.0
    cmd_timeout: Annotated[NonNegative, Meta(
        description="dead-man: stop after this long without cmd_vel")] = 0.5
    robot_radius: Annotated[Positive, Meta(description="the round body's radius (m)")] = 0.2
    start_pose: PoseList = msgspec.field(default_factory=list)
    seed: Annotated[int, Meta(description="random seed for noise; 0 = random")] = 0
    map_frame: str = "map"
    odom_frame: str = "odom"
    base_frame: str = "base_link"


DeviceParameters = tuple[tuple[type[Device[Any]], msgspec.Struct], ...]


@dataclass(frozen=True)
class ChassisConfig:
    """Everything the chassis reads from its parameters (docs/chassis.md lists them)."""

    map_path: Path
    speed: float
    publish_clock: bool
    rate: float
    robot_radius: float
    limits: DriveLimits
    start: Pose2 | None
    seed: int
    frames: Frames = field(default_factory=Frames)
    devices: DeviceParameters = ()

    def build(self, logger: logging.Logger) -> Chassis:
        """Load the map, place the body, fit the devices (raises ValueError/MapError when it
        can't)."""
        grid_map = load_map(self.map_path)
        poses = load_poses(self.map_path)
        world = World(grid_map)
        start = self.start or (Pose2(*poses.start) if poses.start else None)
        sim = Simulation(world=world, drive=Drive(self.limits),
                         truth=start_pose(world, self.robot_radius, start),
                         radius=self.robot_radius)
        chassis = Chassis(sim=sim, frames=self.frames, step_rate=self.rate,
                          rng=np.random.default_rng(self.seed or None), poses=poses,
                          map_path=self.map_path, pacer=Pacer(1.0 / self.rate, self.speed),
                          logger=logger)
        for kind, params in self.devices:
            chassis.fit(kind, params)
        return chassis


def parameter_structs() -> tuple[type[msgspec.Struct], ...]:
    """The Structs the chassis declares: its own, then each device's, in `DEVICES` order.

    Raises:
        TypeError: two of them declare the same parameter name.
    """
    structs: list[type[msgspec.Struct]] = [ChassisParameters,
                                           *(kind.Parameters for kind in DEVICES)]
    seen: dict[str, str] = {}
    for struct in structs:
        for name in struct.__struct_fields__:
            if name in seen and seen[name] != struct.__name__:
                raise TypeError(f"parameter {name!r} is declared by both {seen[name]} and "
                                f"{struct.__name__}")
            seen[name] = struct.__name__
    return tuple(dict.fromkeys(structs))


def declare_chassis(parameters: Parameters) -> ChassisConfig:
    """Declare the chassis's parameters and its devices' (read-only) and check them.

    Raises:
        InvalidParameterValueError: a value out of its limits, or values that do not go
            together (names them).
    """
    declared = {struct: declare_parameters(parameters, struct, read_only=True)
                for struct in parameter_structs()}
    base = declared[ChassisParameters]
    assert isinstance(base, ChassisParameters)
    return chassis_config(base, tuple((kind, declared[kind.Parameters]) for kind in DEVICES))


def chassis_config(p: ChassisParameters, devices: DeviceParameters = ()) -> ChassisConfig:
    """The configuration from the parameters, with their combinations checked.

    Raises:
        InvalidParameterValueError: parameters that do not go together (names them).
    """
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
        start = pose_from("start_pose", p.start_pose)
    except ValueError as exc:
        raise InvalidParameterValueError(str(exc)) from exc
    return ChassisConfig(
        map_path=Path(p.map) if p.map else DEMO_MAP, speed=p.speed,
        publish_clock=p.publish_clock, rate=p.rate, robot_radius=p.robot_radius,
        limits=limits, start=start, seed=p.seed,
        frames=Frames(map=p.map_frame, odom=p.odom_frame, base=p.base_frame),
        devices=devices)
