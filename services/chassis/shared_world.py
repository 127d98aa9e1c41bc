"""`SharedWorld`: several simulated robots in one world, each seeing the others.

Each chassis publishes its body (a circle at its true pose) on one topic all the robots of the
world share (at ``world_rate`` while it moves, every `KEEPALIVE` s at rest), and keeps the bodies the others publish as round obstacles of its own world: its
laser sees them and its body cannot drive through them, as in a real fleet. A body not heard
for `STALE` seconds (a robot stopped or gone) leaves the world.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from msgspec.structs import astuple
from zenros.msgs.zenros_msgs import Obstacle as ObstacleMsg
from zenros.se2 import Pose2

from .obstacles import Obstacle, ObstacleError
from .world import World

__all__ = ["BODY_PREFIX", "STALE", "SharedWorld"]

BODY_PREFIX = "robot:"  # obstacle ids of other robots' bodies, apart from requested obstacles
STALE = 2.0  # seconds (wall clock) without a body's message before it leaves the world
KEEPALIVE = STALE / 4  # a body at rest is sent again this often (s, wall clock)
MAX_RADIUS = 5.0  # m: a larger body is not a robot (a bad message), refused


class SharedWorld:
    """The other robots of the world, as obstacles in ``world``.

    Args:
        world: this robot's world (its ``obstacles`` get the other bodies).
        me: this robot's id in the shared world (its namespace, e.g. ``/robot3``).
        radius: this robot's body radius.
        clock: a monotonic clock (seconds), for staleness.
    """

    def __init__(self, world: World, me: str, radius: float,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.world = world
        self.me = me
        self.radius = radius
        self._clock = clock
        self._heard: dict[str, float] = {}
        self._sent: ObstacleMsg | None = None
        self._sent_at = -float("inf")
        self.refused = 0

    def body(self, truth: Pose2) -> ObstacleMsg:
        """This robot's body at its true pose, to publish."""
        return ObstacleMsg(id=self.me, shape="circle", x=truth.x, y=truth.y, theta=truth.theta,
                           radius=self.radius)

    def due(self, body: ObstacleMsg) -> bool:
        """Whether to send ``body`` now: when it moved since the last one sent, else every
        `KEEPALIVE` s so that the others keep it (a fleet at rest sends 2 bodies a second
        a robot, not ``world_rate``, and each robot decodes 2 per other robot)."""
        now, sent = self._clock(), self._sent
        if (sent is not None and now - self._sent_at < KEEPALIVE
                and astuple(body) == astuple(sent)):  # not Message.__eq__: 10 a second
            return False
        self._sent, self._sent_at = body, now
        return True

    def on_body(self, msg: ObstacleMsg) -> bool:
        """Take another robot's body into the world; False for this robot's own or a body
        that is not a round robot with a finite pose (counted in ``refused``)."""
        if msg.id == self.me:
            return False
        try:
            if not msg.id or msg.shape != "circle" or not 0 < msg.radius <= MAX_RADIUS:
                raise ObstacleError(f"not a robot body: {msg.id!r} {msg.shape} r={msg.radius}")
            ob = Obstacle(BODY_PREFIX + msg.id, "circle", msg.x, msg.y, msg.theta, msg.radius)
        except ObstacleError:
            self.refused += 1
            return False
        self.world.obstacles[ob.id] = ob
        self._heard[ob.id] = self._clock()
        return True

    def prune(self) -> list[str]:
        """Remove the bodies not heard for `STALE` seconds; return their ids."""
        now = self._clock()
        gone = [i for i, t in self._heard.items() if now - t > STALE]
        for i in gone:
            del self._heard[i]
            self.world.obstacles.pop(i, None)
        return gone
