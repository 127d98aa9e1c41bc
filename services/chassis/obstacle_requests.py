"""Obstacle requests: `sim/set_obstacles` messages applied to a `Simulation`."""

from __future__ import annotations

from collections.abc import Iterable

from zenros.msgs.zenros_msgs import Obstacle as ObstacleMsg
from zenros.msgs.zenros_msgs import SetObstaclesRequest

from .floors import DOOR_PREFIX
from .obstacles import Obstacle, ObstacleError
from .people import PERSON_PREFIX
from .shared_world import BODY_PREFIX
from .sim import Simulation

__all__ = ["WORLD_OWNED", "apply_request", "from_msg", "requested", "to_msgs"]

# obstacle ids the simulation owns (other robots' bodies, people's legs, landing doors): a
# request's `clear` and `replace` keep them, and `requested` leaves them out
WORLD_OWNED = (BODY_PREFIX, PERSON_PREFIX, DOOR_PREFIX)


def requested(obstacles: Iterable[Obstacle]) -> list[Obstacle]:
    """The obstacles of ``obstacles`` that requests put there."""
    return [o for o in obstacles if not o.id.startswith(WORLD_OWNED)]


def _clear(sim: Simulation) -> None:
    obstacles = sim.world.obstacles
    for o in requested(obstacles.values()):
        del obstacles[o.id]


def from_msg(m: ObstacleMsg) -> Obstacle:
    return Obstacle(m.id, m.shape, m.x, m.y, m.theta, m.radius, m.size_x, m.size_y)


def to_msgs(obstacles: Iterable[Obstacle]) -> list[ObstacleMsg]:
    return [ObstacleMsg(id=o.id, shape=o.shape, x=o.x, y=o.y, theta=o.theta, radius=o.radius,
                        size_x=o.size_x, size_y=o.size_y) for o in obstacles]


def apply_request(sim: Simulation, req: SetObstaclesRequest) -> str:
    """Apply ``req`` to the world; return "" or why it was refused (then nothing changed)."""
    try:
        obs = [from_msg(m) for m in req.obstacles]
    except ObstacleError as exc:
        return str(exc)
    ids = [o.id for o in obs]
    if len(set(ids)) != len(ids):
        return f"duplicate obstacle ids in the request: {sorted(ids)}"
    world = sim.world
    if req.op in ("set", "replace"):
        why = sim.check_obstacles(obs)
        if why:
            return why
        if req.op == "replace":
            _clear(sim)
        world.set_obstacles(obs)
        return ""
    if req.op == "clear":
        _clear(sim)
        return ""
    # remove
    names = list(req.ids) + ids
    unknown = [n for n in names if n not in world.obstacles]
    if unknown:
        known = ", ".join(sorted(world.obstacles)) or "none"
        return f"unknown obstacle ids {unknown}; known: {known}"
    world.remove_obstacles(names)
    return ""
