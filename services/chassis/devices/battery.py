"""The battery: ``battery_state`` (sensor_msgs/BatteryState) at 1 Hz; charges on the dock."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.sensor_msgs import BatteryState
from zenros.msgs.std_msgs import Header
from zenros.pubsub import Publisher

from ..battery import Battery, BatteryConfig
from ..device import Chassis, Device, Endpoints
from ..param_types import NonNegative
from .dock import DockDevice

__all__ = ["BatteryDevice", "BatteryParameters", "battery_state"]


class BatteryParameters(msgspec.Struct, kw_only=True, frozen=True):
    battery_capacity: NonNegative = 20.0
    battery_voltage: NonNegative = 24.0
    battery_idle_current: NonNegative = 2.0
    battery_motion_current: NonNegative = 6.0
    battery_turn_current: NonNegative = 2.0
    battery_charge_current: NonNegative = 10.0
    battery_initial: Annotated[float, Meta(ge=0, le=1,
                                           description="state of charge at start")] = 0.9

    def __post_init__(self) -> None:
        self.config()

    def config(self) -> BatteryConfig:
        """The battery model's configuration (raises ValueError for a bad combination)."""
        return BatteryConfig(
            capacity=self.battery_capacity, voltage=self.battery_voltage,
            idle_current=self.battery_idle_current, motion_current=self.battery_motion_current,
            turn_current=self.battery_turn_current, charge_current=self.battery_charge_current,
            initial=self.battery_initial)


class BatteryDevice(Device[BatteryParameters]):
    """The pack (`Battery`): drains with the base's motion, charges while docked; an empty
    one holds the base still (``sim.powered``)."""

    Parameters = BatteryParameters
    rate = 1.0
    _pub: Publisher[BatteryState]

    def __init__(self, params: BatteryParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.battery = Battery(params.config())
        self._dock = chassis.device(DockDevice)
        chassis.sim.powered = not self.battery.empty

    @property
    def docked(self) -> bool:
        return self._dock is not None and self._dock.docked

    def open(self, node: Endpoints) -> None:
        self._pub = node.create_publisher(BatteryState, "battery_state")

    def step(self, dt: float) -> None:
        sim = self.chassis.sim
        self.battery.update(dt, sim.linear, sim.angular, self.docked)
        sim.powered = not self.battery.empty

    def publish(self, stamp: Time) -> None:
        self._pub.publish(battery_state(stamp, self.chassis.frames.base, self.battery,
                                        self.docked))


def battery_state(stamp: Time, frame: str, battery: Battery, docked: bool) -> BatteryState:
    if battery.charging:
        status = BatteryState.POWER_SUPPLY_STATUS_CHARGING
    elif docked and battery.full:
        status = BatteryState.POWER_SUPPLY_STATUS_FULL
    else:
        status = BatteryState.POWER_SUPPLY_STATUS_DISCHARGING
    c = battery.config
    return BatteryState(
        header=Header(stamp=stamp, frame_id=frame),
        voltage=battery.voltage, temperature=25.0, current=battery.current,
        charge=battery.charge, capacity=c.capacity, design_capacity=c.capacity,
        percentage=battery.percentage, power_supply_status=status,
        power_supply_health=1,  # GOOD
        power_supply_technology=2,  # LION
        present=True,
    )
