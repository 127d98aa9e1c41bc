"""sensor_msgs: LaserScan (numpy ranges), BatteryState, Imu, JointState."""

from __future__ import annotations

import msgspec

from ..message import Float32Array, Float64Array, Message, array_field
from .geometry_msgs import Quaternion, Vector3
from .std_msgs import Header


class LaserScan(Message):
    __msgtype__ = "sensor_msgs/LaserScan"
    __bulk__ = True
    header: Header = msgspec.field(default_factory=Header)
    angle_min: float = 0.0
    angle_max: float = 0.0
    angle_increment: float = 0.0
    time_increment: float = 0.0
    scan_time: float = 0.0
    range_min: float = 0.0
    range_max: float = 0.0
    ranges: Float32Array = array_field(Float32Array)
    intensities: Float32Array = array_field(Float32Array)


class BatteryState(Message):
    __msgtype__ = "sensor_msgs/BatteryState"
    header: Header = msgspec.field(default_factory=Header)
    voltage: float = 0.0
    temperature: float = 0.0
    current: float = 0.0
    charge: float = 0.0
    capacity: float = 0.0
    design_capacity: float = 0.0
    percentage: float = 0.0
    power_supply_status: int = 0
    power_supply_health: int = 0
    power_supply_technology: int = 0
    present: bool = True
    cell_voltage: list[float] = msgspec.field(default_factory=list)
    cell_temperature: list[float] = msgspec.field(default_factory=list)
    location: str = ""
    serial_number: str = ""

    POWER_SUPPLY_STATUS_UNKNOWN = 0
    POWER_SUPPLY_STATUS_CHARGING = 1
    POWER_SUPPLY_STATUS_DISCHARGING = 2
    POWER_SUPPLY_STATUS_NOT_CHARGING = 3
    POWER_SUPPLY_STATUS_FULL = 4


def _cov9() -> Float64Array:
    c: Float64Array = array_field(Float64Array, [0.0] * 9)
    return c


class Imu(Message):
    __msgtype__ = "sensor_msgs/Imu"
    header: Header = msgspec.field(default_factory=Header)
    orientation: Quaternion = msgspec.field(default_factory=Quaternion)
    orientation_covariance: Float64Array = _cov9()
    angular_velocity: Vector3 = msgspec.field(default_factory=Vector3)
    angular_velocity_covariance: Float64Array = _cov9()
    linear_acceleration: Vector3 = msgspec.field(default_factory=Vector3)
    linear_acceleration_covariance: Float64Array = _cov9()


class JointState(Message):
    __msgtype__ = "sensor_msgs/JointState"
    header: Header = msgspec.field(default_factory=Header)
    name: list[str] = msgspec.field(default_factory=list)
    position: list[float] = msgspec.field(default_factory=list)
    velocity: list[float] = msgspec.field(default_factory=list)
    effort: list[float] = msgspec.field(default_factory=list)
