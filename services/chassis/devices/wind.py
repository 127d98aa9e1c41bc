"""The wind sensor: ``wind`` (zenros_msgs/WindInfo) at 1 Hz: the wind's speed (mean
``wind_speed`` with gusts of ``wind_gust`` std dev), its 10-minute gust maximum, Beaufort
level and direction. Indoors (the default, ``wind_speed`` 0 and no gusts) it reads calm."""

from __future__ import annotations

import bisect
import math
from collections import deque
from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import WindInfo
from zenros.pubsub import Publisher

from ..device import Chassis, Device, Endpoints
from ..param_types import NonNegative

__all__ = ["BEAUFORT", "WindDevice", "WindParameters", "beaufort"]

BEAUFORT = (0.3, 1.6, 3.4, 5.5, 8.0, 10.8, 13.9, 17.2, 20.8, 24.5, 28.5, 32.7)
"""Upper wind speeds (m/s) of Beaufort forces 0..11; faster is force 12."""
WINDOW = 600.0  # s of sim time the gust maximum covers


def beaufort(speed: float) -> int:
    """The Beaufort force (0..12) of a wind of ``speed`` m/s."""
    return bisect.bisect_left(BEAUFORT, speed)


class WindParameters(msgspec.Struct, kw_only=True, frozen=True):
    wind_speed: Annotated[NonNegative, Meta(description="mean wind speed (m/s; 0 indoors)")] = 0.0
    wind_gust: Annotated[NonNegative, Meta(description="std dev of the gusts (m/s)")] = 0.0
    wind_direction: Annotated[float, Meta(
        ge=0, lt=360, description="where the wind blows from (degrees from north)")] = 0.0


class WindDevice(Device[WindParameters]):
    """A sampled wind: speed and direction drawn each second from the chassis's noise."""

    Parameters = WindParameters
    rate = 1.0
    _node: Endpoints
    _pub: Publisher[WindInfo]

    def __init__(self, params: WindParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self._t = 0.0
        self._gusts: deque[tuple[float, float]] = deque()  # (sim time, speed), a max-queue

    def open(self, node: Endpoints) -> None:
        self._node = node
        self._pub = node.create_publisher(WindInfo, "wind", 10)

    def step(self, dt: float) -> None:
        self._t += dt

    def reading(self) -> WindInfo:
        """One sample of the wind now."""
        p, rng = self.params, self.chassis.rng
        speed = max(0.0, p.wind_speed + (rng.normal(0.0, p.wind_gust) if p.wind_gust else 0.0))
        while self._gusts and self._gusts[-1][1] <= speed:
            self._gusts.pop()
        self._gusts.append((self._t, speed))
        while self._gusts[0][0] < self._t - WINDOW:
            self._gusts.popleft()
        spread = 20.0 * min(1.0, p.wind_gust / p.wind_speed) if p.wind_speed > 0 else 0.0
        direction = math.fmod(p.wind_direction + (rng.normal(0.0, spread) if spread else 0.0)
                              + 360.0, 360.0)
        return WindInfo(header=Header(stamp=self._node.stamp(),
                                      frame_id=self.chassis.frames.base),
                        current_speed=round(speed, 3), max_speed=round(self._gusts[0][1], 3),
                        level=float(beaufort(speed)), direction=round(direction, 1))

    def publish(self, stamp: Time) -> None:
        reading = self.reading()  # sampled every second, so the gust maximum is the wind's
        if self._pub.subscription_count:
            self._pub.publish(reading)
