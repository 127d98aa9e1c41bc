"""``chassis/state`` (zenros_msgs/ChassisState) at 5 Hz and on every change of its flags."""

from __future__ import annotations

import math

from zenros.clock import Time
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import ChassisState
from zenros.pubsub import Publisher

from ..device import Chassis, Device, Endpoints, NoParameters
from .battery import BatteryDevice
from .dock import DockDevice

__all__ = ["StateDevice"]

Flags = tuple[bool, bool, bool, bool, bool]


class StateDevice(Device[NoParameters]):
    """The base's flags (e-stop, bumper, docked, charging, dead-man), the requested speed,
    the achieved real-time factor and the battery's charge, in one message."""

    rate = 5.0
    _pub: Publisher[ChassisState]

    def __init__(self, params: NoParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self._dock = chassis.device(DockDevice)
        self._battery = chassis.device(BatteryDevice)
        self._sent: Flags | None = None

    def flags(self) -> Flags:
        sim = self.chassis.sim
        docked = self._dock is not None and self._dock.docked
        charging = self._battery is not None and self._battery.battery.charging
        return (sim.drive.estop, sim.bumper, docked, charging, sim.drive.timed_out(sim.time))

    def open(self, node: Endpoints) -> None:
        self._pub = node.create_publisher(ChassisState, "chassis/state")

    def changed(self) -> bool:
        return self.flags() != self._sent

    def publish(self, stamp: Time) -> None:
        self._sent = estop, bumper, docked, charging, timeout = self.flags()
        pacer = self.chassis.pacer
        self._pub.publish(ChassisState(
            header=Header(stamp=stamp, frame_id=self.chassis.frames.base), estop=estop,
            bumper=bumper, docked=docked, charging=charging, cmd_timeout=timeout,
            speed=pacer.speed, real_time_factor=pacer.factor,
            battery_percentage=(self._battery.battery.percentage
                                if self._battery is not None else math.nan)))
