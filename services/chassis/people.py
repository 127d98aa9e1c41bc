"""Simulated people: `Walker`, a person walking a route with two swinging legs, who steps
aside (up to `MAX_ASIDE` m off their route, where the map is free) while the robot's body is
in their way, or waits when they cannot; `parse_route`, a route as the ``people`` parameter
writes it.

A person is a point walking at ``speed`` along straight segments through the waypoints
(back and forth, or round when ``loop``). Their legs are two circles of `LEG_RADIUS`,
`HIP` m either side of the walking line, each swinging ahead and behind by up to `SWING` m
with the gait (a stride of `STRIDE` m): what a laser at knee height sees of a pedestrian.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from .obstacles import Obstacle

__all__ = ["ASIDE_ROOM", "CLEARANCE", "HIP", "LEG_RADIUS", "MAX_ASIDE", "MAX_PEOPLE",
           "MAX_WAYPOINTS", "PERSON_PREFIX", "STRIDE", "SWING", "Route", "RouteError",
           "Walker", "blocked_by", "parse_route", "uwb_walker"]

PERSON_PREFIX = "person:"  # obstacle ids of people's legs: person:<id>:l, person:<id>:r
LEG_RADIUS = 0.06  # m
HIP = 0.1  # m from the walking line to each leg's centre
SWING = 0.15  # m a leg swings ahead of / behind the hip
STRIDE = 0.7  # m walked per half gait cycle (one leg's swing forward)
CLEARANCE = 0.3  # m a person keeps from the robot's body (their half width and a margin)
MAX_ASIDE = 0.8  # m a person steps off their route to let the robot by
ASIDE_ROOM = HIP + LEG_RADIUS + 0.05  # m from the walls a person stepping aside keeps
MAX_SPEED = 3.0  # m/s: faster is not walking
MAX_WAYPOINTS = 100  # a person's route
MAX_PEOPLE = 50  # in one world: each costs the laser and the cameras a cast per step


class RouteError(ValueError):
    """A route with bad waypoints, speed or id."""


@dataclass(frozen=True)
class Route:
    """``waypoints`` (x, y in ``map``, at least one), walked at ``speed`` m/s; round when
    ``loop``, else back and forth; ``uwb``: the person carries the UWB tag."""

    id: str
    waypoints: tuple[tuple[float, float], ...]
    speed: float = 1.0
    loop: bool = False
    uwb: bool = False

    def __post_init__(self) -> None:
        if not self.id or any(c in self.id for c in " :/*$?#="):
            raise RouteError(f"person id {self.id!r}: expected a non-empty name without "
                             "spaces or any of : / * $ ? # =")
        if not 1 <= len(self.waypoints) <= MAX_WAYPOINTS:
            raise RouteError(f"person {self.id!r}: a route needs 1 to {MAX_WAYPOINTS} "
                             f"waypoints, got {len(self.waypoints)}")
        if not all(math.isfinite(v) for p in self.waypoints for v in p):
            raise RouteError(f"person {self.id!r}: every waypoint must be finite")
        if not (math.isfinite(self.speed) and 0 <= self.speed <= MAX_SPEED):
            raise RouteError(f"person {self.id!r}: speed must be 0..{MAX_SPEED:g} m/s, "
                             f"got {self.speed}")


def parse_route(text: str) -> Route:
    """A route as written in the ``people`` parameter: ``id=x,y;x,y;...`` then optional
    words ``speed=<m/s>``, ``loop``, ``uwb`` (``alice=1,0;4,0 speed=0.8 uwb``).

    Raises:
        RouteError: not in that form (says what was expected).
    """
    words = text.split()
    head = words[0] if words else ""
    name, eq, points = head.partition("=")
    if not eq:
        raise RouteError(f"person {text!r}: expected id=x,y;x,y[;...] [speed=S] [loop] [uwb]")
    try:
        waypoints = tuple((float(x), float(y)) for x, y in
                          (p.split(",") for p in points.split(";") if p))
    except ValueError as exc:
        raise RouteError(f"person {text!r}: waypoints must be x,y pairs of numbers split "
                         "by ';'") from exc
    speed, loop, uwb = 1.0, False, False
    for word in words[1:]:
        if word == "loop":
            loop = True
        elif word == "uwb":
            uwb = True
        elif word.startswith("speed="):
            try:
                speed = float(word[6:])
            except ValueError as exc:
                raise RouteError(f"person {text!r}: speed must be a number") from exc
        else:
            raise RouteError(f"person {text!r}: unknown word {word!r} (speed=S, loop, uwb)")
    return Route(name, waypoints, speed, loop, uwb)


@dataclass
class Walker:
    """A person walking ``route``; `step` moves them unless ``blocked`` says the robot is in
    the way (then they step aside, ``offset`` m left of their route, or wait, ``waiting``
    true); once past, they drift back onto it."""

    route: Route
    x: float = field(init=False)
    y: float = field(init=False)
    theta: float = 0.0
    walked: float = 0.0  # m, for the gait's phase
    waiting: bool = False
    offset: float = 0.0  # m left of the route (stepped aside for the robot)
    _bx: float = field(init=False)  # the route's point they are abreast of
    _by: float = field(init=False)
    _leg: int = 0  # index of the segment's start in `_path`
    _along: float = 0.0  # m along the segment

    def __post_init__(self) -> None:
        pts = list(self.route.waypoints)
        if self.route.loop and len(pts) > 1:
            pts.append(pts[0])
        elif len(pts) > 1:
            pts += pts[-2::-1]  # back the same way
        self._path = pts
        self.x, self.y = self._bx, self._by = pts[0]
        if len(pts) > 1:
            self.theta = math.atan2(pts[1][1] - pts[0][1], pts[1][0] - pts[0][0])

    @property
    def id(self) -> str:
        return self.route.id

    @property
    def speed(self) -> float:
        return 0.0 if self.waiting or len(self._path) < 2 else self.route.speed

    def _advance(self, distance: float) -> tuple[int, float, float, float, float]:
        """Where ``distance`` m further along the path ends: segment, along, x, y, heading."""
        path, leg, along = self._path, self._leg, self._along + distance
        theta = self.theta
        for _ in range(len(path) * 4 + 4):
            (x0, y0), (x1, y1) = path[leg], path[(leg + 1) % len(path)]
            length = math.hypot(x1 - x0, y1 - y0)
            if length > 1e-9:
                theta = math.atan2(y1 - y0, x1 - x0)
            if along <= length:
                f = along / length if length > 1e-9 else 0.0
                return leg, along, x0 + f * (x1 - x0), y0 + f * (y1 - y0), theta
            along -= length
            leg = (leg + 1) % (len(path) - 1) if len(path) > 1 else 0
        return leg, 0.0, path[leg][0], path[leg][1], theta

    def step(self, dt: float, blocked: Callable[[float, float, float, float], bool],
             robot: tuple[float, float] | None = None,
             free: Callable[[float, float], bool] | None = None) -> None:
        """Walk ``dt`` seconds, unless ``blocked(from_x, from_y, to_x, to_y)`` says the step
        is in the robot's way: then step aside, away from the ``robot`` (x, y), where
        ``free(x, y)`` says there is room, or wait where they are."""
        if len(self._path) < 2 or self.route.speed <= 0:
            return
        step = self.route.speed * dt
        leg, along, bx, by, theta = self._advance(step)
        back = math.copysign(min(abs(self.offset), step / 2), self.offset)
        x, y = _abreast(bx, by, theta, self.offset - back)
        if not blocked(self.x, self.y, x, y):
            self.waiting = False
            self.walked += math.hypot(x - self.x, y - self.y)
            self._leg, self._along, self.theta = leg, along, theta
            self._bx, self._by, self.offset, self.x, self.y = bx, by, self.offset - back, x, y
            return
        self.waiting = not self._step_aside(step, blocked, robot, free)

    def _step_aside(self, step: float, blocked: Callable[[float, float, float, float], bool],
                    robot: tuple[float, float] | None,
                    free: Callable[[float, float], bool] | None) -> bool:
        """One step sideways, away from the robot; False when there is no room."""
        if robot is None or free is None:
            return False
        hx, hy = math.cos(self.theta), math.sin(self.theta)
        left = hx * (robot[1] - self.y) - hy * (robot[0] - self.x) > 0  # the robot is left
        offset = max(-MAX_ASIDE, min(MAX_ASIDE, self.offset + (-step if left else step)))
        x, y = _abreast(self._bx, self._by, self.theta, offset)
        if offset == self.offset or not free(x, y) or blocked(self.x, self.y, x, y):
            return False
        self.walked += math.hypot(x - self.x, y - self.y)
        self.offset, self.x, self.y = offset, x, y
        return True

    def legs(self) -> tuple[Obstacle, Obstacle]:
        """The two legs as obstacles, swung by the gait (both beside the hips at rest)."""
        swing = SWING * math.sin(math.pi * self.walked / STRIDE)
        c, s = math.cos(self.theta), math.sin(self.theta)
        out = []
        for side, ahead, tag in ((1.0, swing, "l"), (-1.0, -swing, "r")):
            lx = self.x + ahead * c - side * HIP * s
            ly = self.y + ahead * s + side * HIP * c
            out.append(Obstacle(f"{PERSON_PREFIX}{self.id}:{tag}", "circle", lx, ly,
                                radius=LEG_RADIUS))
        return out[0], out[1]


def _abreast(bx: float, by: float, theta: float, offset: float) -> tuple[float, float]:
    """The point ``offset`` m left of (bx, by) for a walker heading ``theta``."""
    return bx - offset * math.sin(theta), by + offset * math.cos(theta)


def blocked_by(x0: float, y0: float,
               radius: float) -> Callable[[float, float, float, float], bool]:
    """A ``blocked`` test for a robot body of ``radius`` at (x0, y0): a step that ends
    within `CLEARANCE` of it and nearer than it began (walking away is never blocked)."""
    reach = radius + CLEARANCE

    def blocked(fx: float, fy: float, tx: float, ty: float) -> bool:
        to = math.hypot(tx - x0, ty - y0)
        return to < reach and to < math.hypot(fx - x0, fy - y0)

    return blocked


def uwb_walker(walkers: Sequence[Walker]) -> Walker | None:
    """The person carrying the UWB tag, if any."""
    return next((w for w in walkers if w.route.uwb), None)
