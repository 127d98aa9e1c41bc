"""The 2-D laser: ``scan`` (sensor_msgs/LaserScan, ranges and intensities) at ``scan_rate``,
base_link -> laser on ``/tf_static``."""

from __future__ import annotations

import math
from typing import Annotated

import msgspec
import numpy as np
from msgspec import Meta
from zenros.clock import Time
from zenros.errors import MapError
from zenros.maps import load_landmarks
from zenros.message import Float32Array, to_array
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.std_msgs import Header
from zenros.pubsub import Publisher
from zenros.qos import QOS_SENSOR
from zenros.se2 import Pose2

from .. import messages
from ..device import Chassis, Device, Endpoints
from ..laser import Laser, LaserConfig
from ..param_types import NonNegative, Positive
from ..reflectors import Reflectors

__all__ = ["LaserDevice", "LaserParameters", "laser_scan"]


class LaserParameters(msgspec.Struct, kw_only=True, frozen=True):
    scan_rate: Annotated[Positive, Meta(description="scans per sim second")] = 10.0
    scan_beams: int = 360
    range_min: NonNegative = 0.05
    range_max: Positive = 12.0
    scan_fov: NonNegative = 2 * math.pi
    range_noise: Annotated[NonNegative, Meta(
        description="std dev of laser range noise (m)")] = 0.0
    laser_x: float = 0.1
    laser_y: float = 0.0
    laser_yaw: float = 0.0
    laser_z: float = 0.2
    laser_frame: str = "laser"
    laser_error_x: Annotated[float, Meta(
        ge=-0.5, le=0.5, description="how far the laser really sits from laser_x (m)")] = 0.0
    laser_error_y: Annotated[float, Meta(
        ge=-0.5, le=0.5, description="how far the laser really sits from laser_y (m)")] = 0.0
    laser_error_yaw: Annotated[float, Meta(
        ge=-0.5, le=0.5, description="how far the laser is really turned from laser_yaw "
                                     "(rad)")] = 0.0

    def __post_init__(self) -> None:
        if self.range_min >= self.range_max:
            raise ValueError(
                f"parameters 'range_min' ({self.range_min:g}) and 'range_max' "
                f"({self.range_max:g}): range_min must be below range_max")
        self.config()

    def config(self) -> LaserConfig:
        """The ray caster's configuration (raises ValueError for a bad combination)."""
        return LaserConfig(beams=self.scan_beams, range_min=self.range_min,
                           range_max=self.range_max, fov=self.scan_fov, noise=self.range_noise)

    @property
    def mount(self) -> Pose2:
        """The laser's pose on the base as configured (what ``/tf_static`` says)."""
        return Pose2(self.laser_x, self.laser_y, self.laser_yaw)

    @property
    def true_mount(self) -> Pose2:
        """Where the laser really is on the base: the configured mount and its error (what a
        laser calibration measures)."""
        return Pose2(self.laser_x + self.laser_error_x, self.laser_y + self.laser_error_y,
                     self.laser_yaw + self.laser_error_yaw)


class LaserDevice(Device[LaserParameters]):
    """A `Laser` at ``mount`` on the body, ray cast against the world (map, obstacles and
    the other robots) when a scan is due and someone listens; its intensities are strong
    on the reflectors of the map folder's ``landmarks.yaml``."""

    Parameters = LaserParameters
    _pub: Publisher[LaserScan]
    _node: Endpoints

    def __init__(self, params: LaserParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.laser = Laser(chassis.sim.world, params.config(), chassis.rng)
        self.mount = params.mount  # as published; a laser calibration may correct it
        self.true_mount = params.true_mount
        self.rate = params.scan_rate
        cfg = self.laser.config
        self._angles = cfg.angle_min + np.arange(cfg.beams) * cfg.angle_increment
        self._world_generation = self._generation()
        self.reflectors = self._load_reflectors()
        # the last intensities and what they were worked out from (pose, reflectors, ranges)
        self._lit: tuple[tuple[Pose2, Reflectors], np.ndarray, np.ndarray] | None = None

    def _generation(self) -> int:
        return int(getattr(self.chassis.sim.world, "generation", 0))

    def _load_reflectors(self) -> Reflectors:
        """The reflectors of the map the world holds now (the file it was loaded from, else
        the chassis's ``map_path``); none, with a warning, if the file is bad."""
        try:
            return Reflectors(load_landmarks(self.chassis.sim.world.map.source
                                             or self.chassis.map_path))
        except MapError as exc:
            self.chassis.logger.warning("no reflectors for the laser: %s", exc)
            return Reflectors()

    def set_reflectors(self, reflectors: Reflectors) -> None:
        """The reflectors of the map the robot is on from now on (a floor change)."""
        self.reflectors = reflectors

    def ranges(self) -> np.ndarray:
        """The ranges from where the laser is now."""
        p = self.chassis.sim.truth * self.true_mount
        return self.laser.ranges(p.x, p.y, p.theta)

    def scan(self) -> tuple[np.ndarray, np.ndarray]:
        """The ranges and intensities from where the laser is now. After the world took
        another map (a floor change), the reflectors are read again, beside that map's
        YAML."""
        if self._generation() != self._world_generation:
            self._world_generation = self._generation()
            self.reflectors = self._load_reflectors()
        p = self.chassis.sim.truth * self.true_mount
        ranges = self.laser.ranges(p.x, p.y, p.theta)
        return ranges, self._intensities(p, ranges)

    def _intensities(self, p: Pose2, ranges: np.ndarray) -> np.ndarray:
        """The intensities of ``ranges`` cast from ``p``: those of the last scan again when
        it was cast from there, with those reflectors, and gave the same ranges (a robot at
        rest without range noise)."""
        key, lit = (p, self.reflectors), self._lit
        if lit is not None and lit[0] == key and np.array_equal(lit[1], ranges):
            return lit[2].copy()
        out = self.reflectors.intensities(p.x, p.y, p.theta, self._angles, ranges,
                                          self.laser.config.range_max)
        self._lit = (key, ranges.copy(), out.copy())
        return out

    def open(self, node: Endpoints) -> None:
        self._node = node
        self._pub = node.create_publisher(LaserScan, "scan", QOS_SENSOR)
        self._send_mount()

    def set_mount(self, mount: Pose2) -> None:
        """Publish ``mount`` as the laser's pose on the base from now on (a calibration's
        result; the laser itself stays where it is)."""
        self.mount = mount
        self._send_mount()

    def _send_mount(self) -> None:
        self._node.static_transform(messages.transform(
            self._node.stamp(), self.chassis.frames.base, self.params.laser_frame,
            self.mount, self.params.laser_z))

    def publish(self, stamp: Time) -> None:
        if self._pub.subscription_count:
            ranges, intensities = self.scan()
            self._pub.publish(laser_scan(stamp, self.params.laser_frame, self.laser.config,
                                         ranges, 1.0 / self.rate, intensities))


def laser_scan(stamp: Time, frame: str, config: LaserConfig, ranges: np.ndarray,
               scan_time: float, intensities: np.ndarray | None = None) -> LaserScan:
    scan_ranges: Float32Array = to_array(Float32Array, ranges)  # a view: float32 already
    scan_intensities: Float32Array = to_array(
        Float32Array, intensities if intensities is not None else ())
    return LaserScan(
        header=Header(stamp=stamp, frame_id=frame),
        angle_min=config.angle_min, angle_max=config.angle_max,
        angle_increment=config.angle_increment, time_increment=0.0, scan_time=scan_time,
        range_min=config.range_min, range_max=config.range_max, ranges=scan_ranges,
        intensities=scan_intensities,
    )
