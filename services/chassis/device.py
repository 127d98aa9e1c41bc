"""`Device`: one part of the simulated robot (a sensor, an actuator) as one object.

A device is a class, listed once in `devices.DEVICES`, with:

- ``Parameters``: a msgspec Struct whose fields are its chassis parameters (flat names, as
  users pass them: ``scan_rate``, ``battery_capacity``), their only defaults and limits; a
  ``__post_init__`` checks the combinations (raise ``ValueError`` naming the parameters).
- ``__init__(params, chassis)``: builds its model on the `Chassis` (the body and its world,
  the frames, the noise generator, the map folder's poses, the devices fitted before it).
- ``rate``: calls of ``publish`` per sim second (0: none on a schedule).
- ``open(node)``: makes its publishers, subscriptions and services on the node (`Endpoints`).
- ``step(dt)``: every physics step, after the body moved (`Simulation.step`).
- ``publish(stamp)``: at its rate, and whenever ``changed()`` says so.

The node declares every device's parameters, fits them to the `Chassis` in `DEVICES` order,
opens them, steps them after the body and publishes them on one `Schedule`; a device finds
the devices fitted before it with ``chassis.device(Kind)``. No Zenoh here: a device sees the node only as
`Endpoints`, so the tests drive it with a stand-in.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Generic, Protocol, TypeVar

import msgspec
import numpy as np
from zenros.clock import Time
from zenros.maps import MapPoses
from zenros.message import Message, ServiceType
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.pubsub import Publisher
from zenros.qos import QoSProfile
from zenros.tf import TransformBroadcaster

from .pacer import Pacer
from .sim import Simulation

__all__ = ["Chassis", "Device", "Endpoints", "Frames", "NoParameters", "Schedule"]

P = TypeVar("P", bound=msgspec.Struct)
M = TypeVar("M", bound=Message)
D = TypeVar("D", bound="Device[Any]")


class NoParameters(msgspec.Struct, frozen=True):
    """The parameters of a device that has none."""


@dataclass(frozen=True)
class Frames:
    """The frame ids every device may stamp with (parameters ``map_frame``, ...)."""

    map: str = "map"
    odom: str = "odom"
    base: str = "base_link"


@dataclass(frozen=True)
class Chassis:
    """The simulated robot: the body in its world (``sim``) and the devices fitted to it.

    Also what a device is built with: the frame ids, the physics ``step_rate`` (steps per
    sim second), the one noise generator, the map folder's ``poses`` (``map_path``'s
    poses.yaml), the ``pacer`` (speed and achieved factor) and the logger.
    """

    sim: Simulation
    frames: Frames
    step_rate: float
    rng: np.random.Generator
    poses: MapPoses
    map_path: Path
    pacer: Pacer
    logger: logging.Logger
    devices: list[Device[Any]] = field(default_factory=list)
    # the steps of the devices that have one (`Device.step` does nothing: not called)
    _steps: list[Callable[[float], None]] = field(default_factory=list, init=False,
                                                  repr=False, compare=False)

    def fit(self, kind: type[D], params: msgspec.Struct) -> D:
        """Build a ``kind`` device with ``params`` on this chassis and fit it (last)."""
        device = kind(params, self)
        self.devices.append(device)
        if not device.inert and type(device).step is not Device.step:
            self._steps.append(device.step)
        return device

    def device(self, kind: type[D]) -> D | None:
        """The first fitted device of type ``kind``, or None."""
        for d in self.devices:
            if isinstance(d, kind):
                return d
        return None

    def step(self, dt: float) -> None:
        """Move the body by ``dt`` sim seconds, then step every device in order (but those
        with nothing to step: no ``step`` of their own, or ``inert``)."""
        self.sim.step(dt)
        for step in self._steps:
            step(dt)


class Endpoints(Protocol):
    """The node as a device sees it (`ChassisNode`). Callbacks of ``listen`` and ``serve``
    run under the simulation's lock, so they may change the world and the devices."""

    @property
    def namespace(self) -> str: ...

    @property
    def logger(self) -> logging.Logger: ...

    def create_publisher(self, msg_type: type[M], topic: str,
                         qos: QoSProfile | int = 10) -> Publisher[M]: ...

    def listen(self, msg_type: type[M], topic: str, callback: Callable[[M], object],
               qos: QoSProfile | int = 10) -> None: ...

    def serve(self, srv_type: ServiceType, name: str,
              handler: Callable[[Any], Message]) -> None: ...

    def transforms(self) -> TransformBroadcaster: ...

    def static_transform(self, transform: TransformStamped) -> None: ...

    def stamp(self) -> Time: ...


class Device(Generic[P]):
    """Base of the chassis's devices: every hook does nothing until a device overrides it."""

    Parameters: ClassVar[type[msgspec.Struct]] = NoParameters
    rate: float = 0.0
    # True for a device its parameters leave out (no board, no axes, a rate of 0), set in
    # ``__init__``: it is never stepped, asked whether it changed nor published
    inert: bool = False

    def __init__(self, params: P, chassis: Chassis) -> None:
        self.params = params
        self.chassis = chassis

    def open(self, node: Endpoints) -> None:
        """Make the device's publishers, subscriptions and services."""

    def step(self, dt: float) -> None:
        """Advance the device by ``dt`` sim seconds (the body has moved already)."""

    def publish(self, stamp: Time) -> None:
        """Publish what the device measures, stamped ``stamp``."""

    def changed(self) -> bool:
        """True to publish now, off the schedule (checked every step)."""
        return False


class Schedule:
    """Which devices publish on which physics step: every ``round(step_rate / rate)`` steps
    (at least 1; never for a rate of 0), and any step their ``changed()`` is true."""

    def __init__(self, devices: Sequence[Device[Any]], step_rate: float) -> None:
        self.entries = [(d, max(1, round(step_rate / d.rate)) if d.rate > 0 else 0,
                         type(d).changed is not Device.changed) for d in devices]
        # the others never publish
        self._due = [e for e in self.entries if not e[0].inert and (e[1] or e[2])]

    def every(self, device: Device[Any]) -> int:
        """Every how many steps ``device`` publishes on schedule (0: never)."""
        return next(n for d, n, _ in self.entries if d is device)

    def publish(self, step: int, stamp: Time) -> None:
        """Publish the devices due on ``step``, in their order."""
        for device, every, watches in self._due:
            if (every and step % every == 0) or (watches and device.changed()):
                device.publish(stamp)
