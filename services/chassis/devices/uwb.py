"""The UWB anchor: ``uwb/target`` (zenros_msgs/UwbTarget) at ``uwb_rate``, the range and
bearing from the robot to the person carrying the UWB tag (`PeopleDevice`), with the
anchor's noise (`uwb_reading`); nothing while nobody carries the tag."""

from __future__ import annotations

import math
from typing import Annotated

import msgspec
import numpy as np
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import UwbTarget
from zenros.pubsub import Publisher
from zenros.se2 import Pose2, wrap_angle

from ..device import Chassis, Device, Endpoints
from ..param_types import NonNegative, Positive
from ..people import uwb_walker
from .people import PeopleDevice

__all__ = ["UwbDevice", "UwbParameters", "uwb_reading"]


class UwbParameters(msgspec.Struct, kw_only=True, frozen=True):
    uwb_rate: Annotated[Positive, Meta(
        description="uwb/target readings per sim second while a person carries the tag")] = 10.0
    uwb_range_noise: Annotated[NonNegative, Meta(
        description="std dev of the UWB range (m)")] = 0.05
    uwb_bearing_noise: Annotated[NonNegative, Meta(
        description="std dev of the UWB bearing (rad)")] = 0.05


def uwb_reading(robot: Pose2, x: float, y: float, rng: np.random.Generator,
                range_noise: float, bearing_noise: float) -> tuple[float, float]:
    """(range m, bearing rad in the robot's frame) of a tag at (x, y) in ``map``, each with
    Gaussian noise of the given std dev; the range never below 0."""
    dx, dy = x - robot.x, y - robot.y
    r = math.hypot(dx, dy) + (rng.normal(0.0, range_noise) if range_noise else 0.0)
    b = math.atan2(dy, dx) - robot.theta + (rng.normal(0.0, bearing_noise)
                                            if bearing_noise else 0.0)
    return max(0.0, r), wrap_angle(b)


class UwbDevice(Device[UwbParameters]):
    """Reads the tagged person's position off the `PeopleDevice` (fitted before it)."""

    Parameters = UwbParameters
    _node: Endpoints
    _pub: Publisher[UwbTarget] | None = None

    def __init__(self, params: UwbParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.rate = params.uwb_rate
        self.people = chassis.device(PeopleDevice)

    def open(self, node: Endpoints) -> None:
        self._node = node

    def reading(self) -> tuple[float, float] | None:
        """The tag's (range, bearing) now, or None when nobody carries it."""
        tagged = uwb_walker(list(self.people.walkers.values())) if self.people else None
        if tagged is None:
            return None
        p = self.params
        return uwb_reading(self.chassis.sim.truth, tagged.x, tagged.y, self.chassis.rng,
                           p.uwb_range_noise, p.uwb_bearing_noise)

    def publish(self, stamp: Time) -> None:
        reading = self.reading()
        if reading is None:
            return
        if self._pub is None:  # made with the first tag: a robot alone declares nothing
            self._pub = self._node.create_publisher(UwbTarget, "uwb/target", 10)
        if self._pub.subscription_count:
            self._pub.publish(UwbTarget(
                header=Header(stamp=stamp, frame_id=self.chassis.frames.base),
                range=round(reading[0], 4), bearing=round(reading[1], 4)))
