"""`Car`: one simulated elevator car, a state machine stepped with explicit times (plain
Python, no Zenoh; docs/building.md, "The elevator controller").

Jobs are served first come, first served: a robot's ``call`` (the car comes, opens and waits
for the robot to enter, ``WAITING_IN``; the robot's ``go`` rides it to its floor, where the
car waits for it to leave, ``WAITING_OUT``; its ``release`` ends the job) or a person's
``to_level`` (the car comes, opens, dwells ``dwell_s``). One robot holds the car at a time,
whatever its ``capacity``. The doors never close on a body in the doorway (they open again),
and the car never moves unless they are fully closed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Literal

from zenros.building import Elevator
from zenros.msgs.zenros_msgs.elevator import ElevatorState

from .bodies import Body

__all__ = ["MAX_JOBS", "MAX_STEP", "Car", "CarError", "Phase"]

MAX_JOBS = 64  # calls one car keeps queued (a bound on bad input, far above any building's)
MAX_STEP = 1.0  # s: a longer step (or one back in time) is a leap of the clock, not motion


class CarError(ValueError):
    """A command the car refuses; the message says why and what would be valid."""


class Phase(Enum):
    TO_LEVEL = "to_level"        # the car goes to the job's level
    WAITING_IN = "WAITING_IN"    # open at the robot's call floor, waiting for it to enter
    RIDING = "riding"            # the robot sent go: close (once clear), ride
    WAITING_OUT = "WAITING_OUT"  # open at the robot's floor, waiting for it to leave
    DWELL = "dwell"              # a person's call: open for dwell_s


@dataclass
class Job:
    level: int              # where the car goes for it now (the call's, then the ride's)
    robot: str = ""         # "": a person's call (to_level)
    phase: Phase = Phase.TO_LEVEL
    until: float = math.inf  # WAITING_*: when the claim lapses; DWELL: when the doors may close


_OPEN = (Phase.WAITING_IN, Phase.WAITING_OUT, Phase.DWELL)


class Car:
    """One car of ``spec``, at its start level with its doors closed at time ``now`` (s).

    Commands (`call`, `go`, `release`, `to_level`, `open`, `close`) return what they did or
    raise `CarError`; `step` moves time on; `snapshot` is the state to publish. ``events``
    collects what happened on its own (a claim lapsed, a holder was lost) for the log.
    """

    def __init__(self, spec: Elevator, now: float = 0.0) -> None:
        self.spec = spec
        self.name = spec.name
        self.position = float(spec.first_level)
        self.level = spec.first_level
        self.door = 0.0                     # 0 closed .. 1 open
        self.moving = False
        self.direction: Literal["UP", "DOWN", "STOP"] = "STOP"
        self.jobs: list[Job] = []
        self.riders: list[str] = []
        self.blocked = False                # a body in the doorway (the light curtain)
        self.hold_open_until = -math.inf    # the door-open button's dwell
        self.events: list[str] = []
        self._carried: set[str] = set()     # riders when the car last left a floor
        self._t = now

    # ------------------------------------------------------------------ commands

    def call(self, robot: str, level: int, now: float) -> str:
        """``robot`` wants the car at ``level``: queued behind the jobs before it."""
        if not robot:
            raise CarError("call needs a robot (a call with no robot is to_level)")
        self._served(level)
        if self.holder == robot:
            raise CarError(f"{robot} already holds {self.name} (state {self.state}); "
                           "send go or release")
        if robot in self.queue:
            raise CarError(f"{robot} is already queued for {self.name} "
                           f"(queue: {', '.join(self.queue)})")
        strangers = [r for r in self.riders if r not in (robot, self.holder)]
        if len(strangers) >= self.spec.capacity:
            raise CarError(f"{self.name} is full: {', '.join(strangers)} inside with no claim "
                           f"(capacity {self.spec.capacity}); call again once they leave")
        self._room()
        self.jobs.append(Job(level, robot))
        ahead = len(self.jobs) - 1
        return f"{robot} called {self.name} to level {level}" + (
            f" ({ahead} call(s) before it)" if ahead else "")

    def go(self, robot: str, level: int, now: float) -> str:
        """The holder sends the car to ``level``: it closes once the doorway is clear."""
        self._served(level)
        head = self._head()
        if head is None or not robot or head.robot != robot:
            raise CarError(f"{robot or 'a robot with no name'} does not hold {self.name} "
                           f"(holder: {self.holder or 'none'}); call it first")
        if head.phase not in (Phase.WAITING_IN, Phase.WAITING_OUT):
            raise CarError(f"{self.name} is {head.phase.value} for {robot} (to level "
                           f"{head.level}); go is for a car waiting with its doors open")
        if level == head.level:
            raise CarError(f"{self.name} is already at level {level}")
        head.level, head.phase, head.until = level, Phase.RIDING, math.inf
        return f"{self.name} takes {robot} to level {level}"

    def release(self, robot: str, now: float) -> str:
        """``robot`` is done, or gives up its claim or its place in the queue."""
        head = self._head()
        if robot and head is not None and head.robot == robot:
            self._end_claim(f"{robot} released {self.name}")
            return f"{robot} released {self.name}"
        for job in self.jobs[1:]:
            if robot and job.robot == robot:
                self.jobs.remove(job)
                return f"{robot} left the queue of {self.name}"
        raise CarError(f"{robot or 'a robot with no name'} neither holds nor waits for "
                       f"{self.name} (holder: {self.holder or 'none'}; queue: "
                       f"{', '.join(self.queue) or 'empty'})")

    def to_level(self, level: int, now: float) -> str:
        """A person's call: the car comes to ``level``, opens and dwells ``dwell_s``."""
        self._served(level)
        if any(not j.robot and j.level == level and j.phase == Phase.TO_LEVEL
               for j in self.jobs):
            return f"{self.name} is already called to level {level}"
        self._room()
        self.jobs.append(Job(level))
        return f"{self.name} called to level {level}"

    def open(self, now: float) -> str:
        """The door-open button: open at the floor the car is stopped at, ``dwell_s``."""
        if self.moving:
            raise CarError(f"{self.name} is moving ({self.direction} at {self.position:.2f}): "
                           "its doors open at its next stop")
        self.hold_open_until = now + self.spec.door_s + self.spec.dwell_s
        return f"{self.name} opens at level {self.level}"

    def close(self, now: float) -> str:
        """The door-close button: close once the doorway is clear (not while a robot holds
        the car open for itself)."""
        head = self._head()
        if head is not None and head.phase in (Phase.WAITING_IN, Phase.WAITING_OUT):
            raise CarError(f"{self.name} is held by {head.robot} ({head.phase.value}): its "
                           "doors stay open until it sends go or release, or hold_s lapses")
        self.hold_open_until = -math.inf
        if head is not None and head.phase == Phase.DWELL:
            head.until = now
        return f"{self.name} closes its doors" + (" once the doorway is clear"
                                                   if self.blocked else "")

    # ------------------------------------------------------------------ time

    def step(self, now: float, bodies: Sequence[Body] = (),
             lost: Mapping[str, Body] | None = None) -> None:
        """Move on to ``now`` (s): read the ``bodies`` (the live ones: light curtain,
        riders), drop a holder ``lost`` (silent past its lease, last seen outside the car),
        lapse claims, arrive, move the doors, ride. A leap of the clock (back, or more than
        `MAX_STEP` on: a simulation's clock starting or jumping) moves nothing."""
        dt = now - self._t
        if not 0.0 <= dt <= MAX_STEP:
            dt = 0.0
        self._t = now
        self._sense(bodies)
        self._check_lost(lost or {})
        self._lapse(now)
        self._arrive(now)
        self._doors(dt, now)
        self._ride(dt)

    def _sense(self, bodies: Sequence[Body]) -> None:
        at = self.stopped_at
        if at is None:
            self.blocked = False
            return
        spec = self.spec
        self.riders = sorted({b.robot for b in bodies if b.level in spec.stops
                              and (b.level == at or b.robot in self._carried)
                              and spec.inside(b.level, b.x, b.y)})
        self.blocked = any(b.level == at and spec.in_doorway(at, b.x, b.y, b.radius)
                           for b in bodies)

    def _check_lost(self, lost: Mapping[str, Body]) -> None:
        head = self._head()
        if head is None or not head.robot or head.robot not in lost:
            return
        b = lost[head.robot]
        if b.level in self.spec.stops and self.spec.inside(b.level, b.x, b.y):
            return
        self._end_claim(f"{head.robot} lost its claim on {self.name}: no body heard within "
                        "its lease, last seen outside the car")

    def _lapse(self, now: float) -> None:
        head = self._head()
        if head is None or now < head.until:
            return
        if head.phase == Phase.DWELL:
            self.jobs.pop(0)
        elif head.phase in (Phase.WAITING_IN, Phase.WAITING_OUT):
            self._end_claim(f"{head.robot}'s claim on {self.name} lapsed "
                            f"({head.phase.value} for {self.spec.hold_s:g} s)")

    def _arrive(self, now: float) -> None:
        head = self._head()
        if head is None or self.moving or self.position != head.level:
            return
        if head.phase == Phase.TO_LEVEL and head.robot:
            head.phase, head.until = Phase.WAITING_IN, now + self.spec.hold_s
        elif head.phase == Phase.RIDING:
            head.phase, head.until = Phase.WAITING_OUT, now + self.spec.hold_s
        elif head.phase == Phase.TO_LEVEL:
            head.phase, head.until = Phase.DWELL, now + self.spec.door_s + self.spec.dwell_s

    def _doors(self, dt: float, now: float) -> None:
        at = self.stopped_at
        if at is None:
            self.door = 0.0
            return
        head = self._head()
        want = ((head is not None and head.phase in _OPEN and head.level == at)
                or now < self.hold_open_until or (self.blocked and self.door > 0.0)
                or self._strangers())
        rate = dt / self.spec.door_s
        self.door = min(1.0, self.door + rate) if want else max(0.0, self.door - rate)

    def _ride(self, dt: float) -> None:
        head = self._head()
        if head is None or head.phase not in (Phase.TO_LEVEL, Phase.RIDING):
            return
        target = float(head.level)
        if self.position == target:
            return
        if not self.moving:
            if self.door > 0.0 or self._t < self.hold_open_until or self._strangers():
                return
            self.moving = True
            self._carried = set(self.riders)
        sign = 1.0 if target > self.position else -1.0
        self.direction = "UP" if sign > 0 else "DOWN"
        step = dt / self.spec.travel_s
        self.position = (target if abs(target - self.position) <= step
                         else self.position + sign * step)
        passed = [lv for lv in self.spec.levels
                  if (lv <= self.position if sign > 0 else lv >= self.position)]
        if passed:
            self.level = max(passed) if sign > 0 else min(passed)
        if self.position == target:
            self.moving, self.direction, self.level = False, "STOP", head.level

    # ------------------------------------------------------------------ views

    @property
    def stopped_at(self) -> int | None:
        """The level the car stands at (doors may open), None while it moves."""
        return None if self.moving else self.level

    @property
    def holder(self) -> str:
        head = self._head()
        return head.robot if head is not None else ""

    @property
    def queue(self) -> list[str]:
        return [j.robot for j in self.jobs[1:] if j.robot]

    @property
    def state(self) -> Literal["NONE", "WAITING_IN", "WAITING_OUT"]:
        head = self._head()
        if head is not None and head.phase == Phase.WAITING_IN:
            return "WAITING_IN"
        if head is not None and head.phase == Phase.WAITING_OUT:
            return "WAITING_OUT"
        return "NONE"

    def snapshot(self) -> ElevatorState:
        """The state to publish (no stamp): door and position to 0.01."""
        head = self._head()
        calls = [j.level for j in self.jobs
                 if j is not head or j.phase in (Phase.TO_LEVEL, Phase.RIDING)]
        return ElevatorState(
            name=self.name, level=self.level, position=round(self.position, 2),
            direction=self.direction, state=self.state, door=round(self.door, 2),
            front_door_open=self.door >= 1.0, back_door_open=False,
            levels=list(self.spec.levels), calls=calls, holder=self.holder, queue=self.queue,
            riders=list(self.riders), capacity=self.spec.capacity)

    # ------------------------------------------------------------------ helpers

    def _head(self) -> Job | None:
        return self.jobs[0] if self.jobs else None

    def _strangers(self) -> bool:
        """Robots aboard that do not hold the car (one paused or stopped in it, one that
        released it still inside): the car stands at its floor, doors open, until they are
        out. It never carries a robot that did not ask to ride: its nav would be on the
        wrong floor's map."""
        head = self._head()
        holder = head.robot if head is not None else ""
        return any(r != holder for r in self.riders)

    def _served(self, level: int) -> None:
        if level not in self.spec.levels:
            raise CarError(f"{self.name} does not serve level {level} (levels "
                           f"{', '.join(str(lv) for lv in self.spec.levels)})")

    def _room(self) -> None:
        if len(self.jobs) >= MAX_JOBS:
            raise CarError(f"{self.name} has {MAX_JOBS} calls waiting already; try later")

    def _end_claim(self, why: str) -> None:
        """The head job's robot is done or gone: a ride under way still ends at its floor
        (as a person's call there); otherwise the next job's turn."""
        head = self.jobs[0]
        self.events.append(why)
        if head.phase == Phase.RIDING and self.moving:
            self.jobs[0] = Job(head.level)
        else:
            self.jobs.pop(0)
