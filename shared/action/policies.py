"""Goal scheduling policies (simple, queue, reject_if_busy, parallel) as a pure state machine.

The `Scheduler` decides which accepted goals run, which wait, and which are preempted; it
knows nothing of Zenoh, threads or goal handles, so tests drive it step by step.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Hashable
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

__all__ = ["POLICY_KINDS", "GoalPolicy", "Plan", "Scheduler"]

K = TypeVar("K", bound=Hashable)

POLICY_KINDS = ("simple", "queue", "reject_if_busy", "parallel")


@dataclass(frozen=True)
class GoalPolicy:
    """How an action server schedules goals.

    - ``simple`` (actionlib's SimpleActionServer, the seed's policy): one goal runs; a new goal
      preempts it (cancel requested) and starts once it has ended; a goal still waiting for
      that is itself replaced (canceled) by a newer one.
    - ``queue``: one goal runs; the others wait in arrival order (at most ``max_waiting``,
      beyond which new goals are rejected).
    - ``reject_if_busy``: one goal runs; a goal sent meanwhile is rejected.
    - ``parallel``: up to ``limit`` goals run at once (None: no limit); the others wait in order.
    """

    kind: str = "simple"
    limit: int | None = 1
    max_waiting: int | None = None

    def __post_init__(self) -> None:
        if self.kind not in POLICY_KINDS:
            raise ValueError(f"unknown goal policy {self.kind!r}; valid: {', '.join(POLICY_KINDS)}")
        if self.limit is not None and self.limit < 1:
            raise ValueError(f"policy limit must be >= 1 or None, got {self.limit}")
        if self.kind != "parallel" and self.limit != 1:
            raise ValueError(f"policy {self.kind} runs one goal at a time; limit must be 1")
        if self.max_waiting is not None and self.max_waiting < 0:
            raise ValueError(f"max_waiting must be >= 0 or None, got {self.max_waiting}")

    @classmethod
    def parallel(cls, limit: int | None = None, max_waiting: int | None = None) -> GoalPolicy:
        return cls("parallel", limit, max_waiting)

    @classmethod
    def queue(cls, max_waiting: int | None = None) -> GoalPolicy:
        return cls("queue", 1, max_waiting)

    @classmethod
    def parse(cls, spec: str | GoalPolicy) -> GoalPolicy:
        """A policy from its name: ``simple``, ``queue``, ``queue:<max_waiting>``,
        ``reject_if_busy``, ``parallel`` (no limit) or ``parallel:<limit>``."""
        if isinstance(spec, GoalPolicy):
            return spec
        kind, _, arg = spec.partition(":")
        if arg and kind not in ("queue", "parallel"):
            raise ValueError(f"policy {kind!r} takes no argument, got {spec!r}")
        try:
            n = int(arg) if arg else None
        except ValueError:
            raise ValueError(f"bad goal policy {spec!r}: expected {kind}:<integer>") from None
        if kind == "parallel":
            return cls.parallel(n)
        if kind == "queue":
            return cls.queue(n)
        return cls(kind)

    def __str__(self) -> str:
        if self.kind == "parallel":
            return f"parallel:{self.limit}" if self.limit else "parallel"
        if self.kind == "queue" and self.max_waiting is not None:
            return f"queue:{self.max_waiting}"
        return self.kind


@dataclass(frozen=True)
class Plan(Generic[K]):
    """What the server must do after an event. ``reject`` (a reason) refuses the offered goal;
    ``start`` goals begin executing, ``preempt`` goals get a cancel request, ``drop`` goals
    (waiting, never run) end canceled."""

    start: tuple[K, ...] = ()
    preempt: tuple[K, ...] = ()
    drop: tuple[K, ...] = ()
    reject: str = ""


_NOTHING: Plan[Any] = Plan()


class Scheduler(Generic[K]):
    """Running and waiting goals under one `GoalPolicy`."""

    def __init__(self, policy: GoalPolicy) -> None:
        self.policy = policy
        self.running: list[K] = []
        self.waiting: deque[K] = deque()
        self._preempted: set[K] = set()

    @property
    def busy(self) -> bool:
        return bool(self.running or self.waiting)

    def _has_room(self) -> bool:
        limit = self.policy.limit
        return limit is None or len(self.running) < limit

    def offer(self, goal: K) -> Plan[K]:
        """A goal was accepted by the goal callback; place it."""
        p = self.policy
        if p.kind == "reject_if_busy" and self.busy:
            return Plan(reject="server busy: another goal is executing (policy reject_if_busy)")
        if p.kind == "simple":
            drop = tuple(self.waiting)
            self.waiting.clear()
            preempt = tuple(g for g in self.running if g not in self._preempted)
            self._preempted.update(preempt)
            if not self.running:
                self.running.append(goal)
                return Plan(start=(goal,), drop=drop)
            self.waiting.append(goal)
            return Plan(preempt=preempt, drop=drop)
        if self._has_room() and not self.waiting:
            self.running.append(goal)
            return Plan(start=(goal,))
        if p.max_waiting is not None and len(self.waiting) >= p.max_waiting:
            return Plan(reject=f"queue full: {len(self.waiting)} goals waiting (policy {p})")
        self.waiting.append(goal)
        return Plan()

    def finish(self, goal: K) -> Plan[K]:
        """A running goal ended (its execute callback returned); start whatever may run now."""
        if goal in self.running:
            self.running.remove(goal)
        self._preempted.discard(goal)
        if not self.waiting:
            return _NOTHING
        start: list[K] = []
        while self.waiting and self._has_room():
            nxt = self.waiting.popleft()
            self.running.append(nxt)
            start.append(nxt)
        return Plan(start=tuple(start))

    def withdraw(self, goal: K) -> bool:
        """Remove a waiting goal (canceled before it ran); False if it is not waiting."""
        try:
            self.waiting.remove(goal)
        except ValueError:
            return False
        return True
