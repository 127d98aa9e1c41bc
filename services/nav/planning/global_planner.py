"""GlobalPlanner: nav's planner server: plans through a list of poses on a costmap snapshot
with the planner plugin a request names, with error codes.

As Nav2's planner server: the plugin (`interface.Planner`, by id, ``planner_plugins``) plans
each leg (start → pose 1 → pose 2 ...); the legs are concatenated, with the arc length at
which each pose is reached. A start inside the inflated zone (the robot next to a wall or on
its dock) is planned out of: the costs within the robot's radius of the start are lowered to
252. `PlanWorker` runs requests on a thread of its own so the control loop never waits.
"""

from __future__ import annotations

import dataclasses
import math
import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from zenros.msgs.nav2_msgs import ComputePathToPoseResult as Codes
from zenros.se2 import Pose2

from ..costmap.snapshot import CostSnapshot
from .errors import PlanningError
from .grid_based import AStarPlanner
from .interface import NoParameters, Planner, PlannerContext
from .plan import PlannerParams

__all__ = ["GlobalPlanner", "PlanOutcome", "PlanWorker"]


@dataclass
class PlanOutcome:
    """A plan (``xy`` points in ``map``) or an error code (ComputePathToPose's)."""

    xy: np.ndarray | None
    error_code: int = 0
    error_msg: str = ""
    leg_ends: list[float] = field(default_factory=list)
    """Arc length along ``xy`` where each requested pose is reached."""
    planning_time: float = 0.0
    goals: list[Pose2] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.xy is not None


class GlobalPlanner:
    """Plans with its plugins (by id; the first is the default), on the snapshot given.

    Without ``planners`` it has one, ``GridBased``: the A* plugin with ``params``."""

    def __init__(self, params: PlannerParams, robot_radius: float,
                 goal_tolerance: float = 0.25,
                 planners: Mapping[str, Planner] | None = None) -> None:
        self.params = params
        self.robot_radius = robot_radius
        self.goal_tolerance = goal_tolerance
        if planners is None:
            context = PlannerContext(params, robot_radius, goal_tolerance)
            planners = {"GridBased": AStarPlanner(NoParameters(), context)}
        if not planners:
            raise ValueError("a planner server needs at least one planner")
        self.planners = dict(planners)

    @property
    def ids(self) -> list[str]:
        """The planner ids, the default first."""
        return list(self.planners)

    def _free_start(self, snap: CostSnapshot, cell: tuple[int, int]) -> CostSnapshot:
        costs = snap.costs.copy()
        r = max(1, math.ceil(self.robot_radius / snap.resolution))
        h, w = costs.shape
        x0, x1 = max(0, cell[0] - r), min(w, cell[0] + r + 1)
        y0, y1 = max(0, cell[1] - r), min(h, cell[1] + r + 1)
        ys, xs = np.mgrid[y0:y1, x0:x1]
        disc = (xs - cell[0]) ** 2 + (ys - cell[1]) ** 2 <= r * r
        win = costs[y0:y1, x0:x1]
        win[disc & (win >= 253) & (win != 255)] = 252
        return dataclasses.replace(snap, costs=costs)

    def plan(self, snap: CostSnapshot, start: Pose2, goals: list[Pose2],
             planner_id: str = "") -> PlanOutcome:
        """Plan from ``start`` through every pose of ``goals`` in order with the planner
        ``planner_id`` ("": the default)."""
        t0 = time.perf_counter()
        planner = self.planners.get(planner_id or self.ids[0])
        if planner is None:
            return PlanOutcome(None, Codes.INVALID_PLANNER,
                               f"unknown planner_id {planner_id!r}; this server has "
                               f"{', '.join(self.planners)}")
        if not goals:
            return PlanOutcome(None, Codes.UNKNOWN, "no goal poses given")
        pieces: list[np.ndarray] = []
        leg_ends: list[float] = []
        here = start
        total = 0.0
        for i, goal in enumerate(goals):
            s = snap.world_to_map(here.x, here.y)
            if s is None:
                code = Codes.START_OUTSIDE_MAP if i == 0 else Codes.GOAL_OUTSIDE_MAP
                return PlanOutcome(None, code, f"({here.x:.2f}, {here.y:.2f}) is outside the map")
            if snap.world_to_map(goal.x, goal.y) is None:
                return PlanOutcome(None, Codes.GOAL_OUTSIDE_MAP,
                                   f"goal ({goal.x:.2f}, {goal.y:.2f}) is outside the map")
            what = f"leg {i + 1} of {len(goals)}: " if len(goals) > 1 else ""
            try:
                pts = np.asarray(planner.create_plan(
                    self._free_start(snap, s) if i == 0 else snap, here, goal), np.float64)
                if pts.ndim != 2 or pts.shape[1] != 2 or not len(pts):
                    raise TypeError(f"a path of shape {pts.shape}, not (N, 2)")
            except PlanningError as exc:
                return PlanOutcome(None, exc.code, what + str(exc),
                                   planning_time=time.perf_counter() - t0)
            except Exception as exc:  # noqa: BLE001 - a plugin's bug fails this plan only
                return PlanOutcome(None, Codes.UNKNOWN,
                                   f"{what}planner {planner_id or self.ids[0]!r} failed: "
                                   f"{exc!r}", planning_time=time.perf_counter() - t0)
            end = pts[-1].copy()
            if pieces:  # this leg starts where the last one ended
                pts = np.vstack([pieces[-1][-1:], pts[1:]])
                total += _length(pts)
                pieces.append(pts[1:])
            else:
                total += _length(pts)
                pieces.append(pts)
            leg_ends.append(total)
            here = Pose2(float(end[0]), float(end[1]), goal.theta)
        xy = np.vstack(pieces) if pieces else np.array([[start.x, start.y]])
        return PlanOutcome(xy, 0, "", leg_ends, time.perf_counter() - t0, list(goals))


def _length(pts: np.ndarray) -> float:
    if len(pts) < 2:
        return 0.0
    d = np.diff(pts, axis=0)
    return float(np.sum(np.hypot(d[:, 0], d[:, 1])))


class PlanWorker:
    """Plans on a background thread; one request at a time, the newest wins.

    With ``threaded=False`` there is no thread: `submit` plans at once, in the caller, and
    the outcome is ready at the next `poll` (deterministic, for driving behaviours tick by
    tick in tests and simulations without wall-clock waits)."""

    def __init__(self, planner: GlobalPlanner, source: object, *, threaded: bool = True) -> None:
        self.planner = planner
        self.source = source  # callable returning a CostSnapshot
        self.threaded = threaded
        self._cond = threading.Condition()
        self._pending: tuple[int, Pose2, list[Pose2]] | None = None
        self._results: dict[int, PlanOutcome] = {}
        self._seq = 0
        self._stop = False
        self._thread: threading.Thread | None = None
        if threaded:
            self._thread = threading.Thread(target=self._run, name="nav-planner", daemon=True)
            self._thread.start()

    def submit(self, start: Pose2, goals: list[Pose2]) -> int:
        """Queue a request (replacing one not started yet); returns its ticket."""
        with self._cond:
            self._seq += 1
            ticket = self._seq
            if self.threaded:
                self._pending = (ticket, start, list(goals))
                self._cond.notify_all()
                return ticket
        self._store(ticket, self._plan(start, list(goals)))
        return ticket

    def poll(self, ticket: int) -> PlanOutcome | None:
        """The outcome of ``ticket`` once it is ready (then forgotten)."""
        with self._cond:
            return self._results.pop(ticket, None)

    def _run(self) -> None:
        while True:
            with self._cond:
                while self._pending is None and not self._stop:
                    self._cond.wait()
                if self._stop:
                    return
                assert self._pending is not None
                ticket, start, goals = self._pending
                self._pending = None
            self._store(ticket, self._plan(start, goals))

    def _plan(self, start: Pose2, goals: list[Pose2]) -> PlanOutcome:
        try:
            snap = self.source()  # type: ignore[operator]
            return self.planner.plan(snap, start, goals)
        except Exception as exc:  # noqa: BLE001 - a planner bug must not kill the thread
            return PlanOutcome(None, Codes.UNKNOWN, f"planner failed: {exc!r}")

    def _store(self, ticket: int, out: PlanOutcome) -> None:
        with self._cond:
            self._results = {k: v for k, v in self._results.items() if k > ticket - 8}
            self._results[ticket] = out
            self._cond.notify_all()

    def close(self) -> None:
        with self._cond:
            self._stop = True
            self._cond.notify_all()
        if self._thread is not None:
            self._thread.join(2.0)
