"""`Body` and `BodyTable`: the robots' bodies in the building as the controller last heard
them (``/building/bodies``), and which of them are live or lost (silent past a lease).

A body is live until it has been silent for ``lease`` seconds of *both* clocks, the node's
(sim time under ``use_sim_time``) and the wall: a simulation run faster than real time
(``speed:=10``) does not shorten the lease in wall time, and a stalled simulation (sim time
standing still) does not lose a body that is only waiting for the world to move.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zenros.msgs.zenros_msgs.elevator import BuildingBody

__all__ = ["Body", "BodyTable", "body_of"]


@dataclass(frozen=True)
class Body:
    """A robot's body: its floor, where it is on that floor's map, its radius (m)."""

    robot: str
    level: int
    x: float
    y: float
    radius: float = 0.2


def body_of(msg: BuildingBody) -> Body | None:
    """``msg`` as a `Body`, or None when it cannot be one (no robot, a coordinate or radius
    that is not a finite number, a negative radius)."""
    if not msg.robot or not all(math.isfinite(v) for v in (msg.x, msg.y, msg.radius)):
        return None
    if msg.radius < 0:
        return None
    return Body(msg.robot, msg.level, msg.x, msg.y, msg.radius)


@dataclass
class _Heard:
    body: Body
    sim: float
    wall: float


class BodyTable:
    """The last body heard of each robot and when, on both clocks (s).

    Args:
        lease: seconds of silence (on both clocks) after which a body is lost.
        forget: seconds of silence (on both clocks) after which it is dropped altogether.
    """

    def __init__(self, lease: float = 5.0, forget: float = 60.0) -> None:
        self.lease = lease
        self.forget = max(forget, lease)
        self._heard: dict[str, _Heard] = {}

    def heard(self, body: Body, sim: float, wall: float) -> None:
        self._heard[body.robot] = _Heard(body, sim, wall)

    def _silent(self, h: _Heard, sim: float, wall: float, limit: float) -> bool:
        return sim - h.sim > limit and wall - h.wall > limit

    def live(self, sim: float, wall: float) -> list[Body]:
        """The bodies heard within the lease."""
        return [h.body for h in self._heard.values()
                if not self._silent(h, sim, wall, self.lease)]

    def lost(self, sim: float, wall: float) -> dict[str, Body]:
        """Robots silent past the lease, by name, with the last body heard; forgets those
        silent past ``forget``."""
        for robot in [r for r, h in self._heard.items()
                      if self._silent(h, sim, wall, self.forget)]:
            del self._heard[robot]
        return {r: h.body for r, h in self._heard.items()
                if self._silent(h, sim, wall, self.lease)}
