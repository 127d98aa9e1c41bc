"""Simulated people (`Walker`): pedestrians walking routes in the world, their legs put in it
as obstacles (``person:<id>:l``/``:r``) so the laser sees them, nav's costmap avoids them and
the cameras draw them; they wait while the robot's body is in their way.

``sim/set_people`` (zenros_msgs/SetPeople) adds, replaces, removes or clears them at run
time; ``sim/people`` (zenros_msgs/People, ground truth for tests and visualisation) at
``people_rate`` while there are any. The ``people`` parameter starts some (`parse_route`).
"""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import (
    People,
    Person,
    PersonRoute,
    SetPeople,
    SetPeopleRequest,
    SetPeopleResponse,
)
from zenros.pubsub import Publisher

from ..device import Chassis, Device, Endpoints
from ..param_types import Positive
from ..people import (
    ASIDE_ROOM,
    MAX_PEOPLE,
    PERSON_PREFIX,
    Route,
    RouteError,
    Walker,
    blocked_by,
    parse_route,
)

__all__ = ["PeopleDevice", "PeopleParameters", "route_from_msg"]


class PeopleParameters(msgspec.Struct, kw_only=True, frozen=True):
    people: Annotated[list[str], Meta(
        description="people walking routes: 'id=x,y;x,y[;...] [speed=S] [loop] [uwb]' "
                    "(map metres; back and forth unless loop; uwb: carries the UWB tag)")] = (
        msgspec.field(default_factory=list))
    people_rate: Annotated[Positive, Meta(
        description="sim/people (ground truth) messages per sim second while people walk")] = 10.0

    def __post_init__(self) -> None:
        self.routes()

    def routes(self) -> list[Route]:
        """The routes of ``people`` (ValueError naming the parameter when bad)."""
        try:
            routes = [parse_route(text) for text in self.people]
            check_routes(routes)
        except RouteError as exc:
            raise ValueError(f"parameter 'people': {exc}") from exc
        return routes


def check_routes(routes: list[Route]) -> None:
    """Raises RouteError for two people of one id, two UWB tags or too many people."""
    if len(routes) > MAX_PEOPLE:
        raise RouteError(f"at most {MAX_PEOPLE} people walk in one world, got {len(routes)}")
    ids = [r.id for r in routes]
    if len(set(ids)) != len(ids):
        raise RouteError(f"two people share an id: {sorted(ids)}")
    if sum(r.uwb for r in routes) > 1:
        raise RouteError("only one person can carry the UWB tag")


def route_from_msg(m: PersonRoute) -> Route:
    """The `Route` of a message (RouteError when bad)."""
    return Route(m.id, tuple((p.x, p.y) for p in m.waypoints), m.speed, m.loop, m.uwb)


class PeopleDevice(Device[PeopleParameters]):
    """The walking people, stepped with the body."""

    Parameters = PeopleParameters
    _node: Endpoints
    _pub: Publisher[People] | None = None

    def __init__(self, params: PeopleParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.rate = params.people_rate
        self.walkers: dict[str, Walker] = {}
        why = self._put([Walker(r) for r in params.routes()], replace=True)
        if why:
            raise ValueError(f"parameter 'people': {why}")

    def open(self, node: Endpoints) -> None:
        self._node = node
        node.serve(SetPeople, "sim/set_people", self.handle_set_people)

    # ---------------------------------------------------------------- the world

    def _put(self, walkers: list[Walker], replace: bool) -> str:
        """Add ``walkers`` (all replaced when ``replace``); "" or why not (nothing changed)."""
        kept = {} if replace else {i: w for i, w in self.walkers.items()
                                   if i not in {n.id for n in walkers}}
        try:
            check_routes([w.route for w in (*kept.values(), *walkers)])
        except RouteError as exc:
            return str(exc)
        legs = [leg for w in walkers for leg in w.legs()]
        why = self.chassis.sim.check_obstacles(legs)
        if why:
            return f"{why}: a person cannot start on the robot"
        self._remove(list(self.walkers) if replace else [w.id for w in walkers])
        kept.update((w.id, w) for w in walkers)
        self.walkers = kept
        self.chassis.sim.world.set_obstacles(legs)
        return ""

    def _remove(self, ids: list[str]) -> None:
        for i in ids:
            if self.walkers.pop(i, None) is not None:
                self.chassis.sim.world.remove_obstacles(
                    [f"{PERSON_PREFIX}{i}:l", f"{PERSON_PREFIX}{i}:r"])

    def step(self, dt: float) -> None:
        if not self.walkers:
            return
        sim = self.chassis.sim
        blocked = blocked_by(sim.truth.x, sim.truth.y, sim.radius)
        world = sim.world
        robot = (sim.truth.x, sim.truth.y)

        def free(x: float, y: float) -> bool:  # room on the map to stand (walls only)
            return world.inside(x, y) and world.map_clearance(x, y, ASIDE_ROOM) >= ASIDE_ROOM

        for w in self.walkers.values():
            w.step(dt, blocked, robot, free)
            world.set_obstacles(w.legs())

    # ---------------------------------------------------------------- endpoints

    def people(self) -> list[Person]:
        return [Person(id=w.id, x=w.x, y=w.y, theta=w.theta, speed=w.speed,
                       waiting=w.waiting, uwb=w.route.uwb) for w in self.walkers.values()]

    def publish(self, stamp: Time) -> None:
        if not self.walkers:
            return
        if self._pub is None:  # made with the first person: a robot alone declares nothing
            self._pub = self._node.create_publisher(People, "sim/people", 10)
        if self._pub.subscription_count:
            self._pub.publish(People(header=Header(stamp=stamp,
                                                   frame_id=self.chassis.frames.map),
                                     people=self.people()))

    def handle_set_people(self, req: SetPeopleRequest) -> SetPeopleResponse:
        why = self._apply(req)
        if not why:
            self._node.logger.info("people: %s", ", ".join(self.walkers) or "none")
        return SetPeopleResponse(success=not why, message=why, people=self.people())

    def _apply(self, req: SetPeopleRequest) -> str:
        if req.op == "clear":
            self._remove(list(self.walkers))
            return ""
        if req.op == "remove":
            unknown = [i for i in req.ids if i not in self.walkers]
            if unknown:
                return (f"unknown people {unknown}; known: "
                        f"{', '.join(sorted(self.walkers)) or 'none'}")
            self._remove(list(req.ids))
            return ""
        try:
            walkers = [Walker(route_from_msg(m)) for m in req.people]
        except RouteError as exc:
            return str(exc)
        if len({w.id for w in walkers}) != len(walkers):
            return f"two people share an id: {sorted(w.id for w in walkers)}"
        return self._put(walkers, replace=req.op == "replace")
