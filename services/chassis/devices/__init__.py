"""The chassis's devices, registered in one place: `DEVICES`.

Their order is the order they are built, stepped after the body and published in, so a
device comes after those it reads (the battery after the dock, chassis/state after both).
A new device is one module here and one line below (docs/chassis.md, Adding a device).
"""

from __future__ import annotations

from typing import Any

from ..device import Device
from .actuators import ActuatorDevice
from .asr import AsrDevice
from .battery import BatteryDevice
from .building import BuildingDevice
from .calibration import CalibrationDevice
from .camera import CameraDevice
from .dock import DockDevice
from .fleet import FleetDevice
from .imu import ImuDevice
from .io import IoDevice
from .laser import LaserDevice
from .microphone import MicrophoneDevice
from .odometry import OdometryDevice
from .people import PeopleDevice
from .ptz import PtzDevice
from .state import StateDevice
from .truth import GroundTruthDevice
from .uwb import UwbDevice
from .wind import WindDevice

__all__ = ["DEVICES", "ActuatorDevice", "AsrDevice", "BatteryDevice", "BuildingDevice",
           "CalibrationDevice",
           "CameraDevice", "DockDevice", "FleetDevice", "GroundTruthDevice", "ImuDevice",
           "IoDevice", "LaserDevice", "MicrophoneDevice",
           "OdometryDevice", "PeopleDevice", "PtzDevice", "StateDevice", "UwbDevice",
           "WindDevice"]

DEVICES: tuple[type[Device[Any]], ...] = (
    BuildingDevice,  # first: a ride changes the floor every other device sees
    OdometryDevice,
    GroundTruthDevice,
    PeopleDevice,  # before the laser and the cameras: they see the people's legs
    UwbDevice,
    DockDevice,
    BatteryDevice,
    LaserDevice,
    ImuDevice,
    CameraDevice,
    CalibrationDevice,
    IoDevice,
    StateDevice,
    FleetDevice,
    WindDevice,
    ActuatorDevice,
    AsrDevice,
    PtzDevice,
    MicrophoneDevice,
)
