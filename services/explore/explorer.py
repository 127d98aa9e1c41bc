"""Explorer: where to drive next, explore_lite's loop (EX src/explore.cpp) as plain Python.

At each planning step (``planner_frequency``, 1 Hz) the node hands `step` the latest map and
the robot's pose. The cheapest frontier whose goal is not blacklisted becomes the target; a
target within ``same_goal_radius`` of the current one is the same goal (no new
navigate_to_pose, since the map moves the centroid a little at every update). A goal that
nav aborts, or that makes no progress (the robot no closer to it by ``progress_distance``)
for ``progress_timeout`` seconds, is blacklisted; so is one reached (the robot turned round
there, Yamauchi's sweep, so the laser saw what it could from there). A frontier's goal is
never within ``blacklist_radius`` of a blacklisted one: it takes its next best spot, and a
frontier with none left is skipped. A goal whose frontier is mapped (or moves away) while the robot
drives to it is overtaken by the next one, and counted with the reached ones in
``goals_reached``. With no frontier left the explorer returns to the start pose
(``return_to_start``), then is done. A map with no free space round the robot is not
explored but not known yet: the explorer waits (`Decision` ``wait``); so does one with no
frontier left until ``confirm_steps`` planning steps in a row, on ``confirm_maps`` grids,
agree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import partial
from typing import Literal

from zenros.maps import GridMap
from zenros.se2 import Pose2

from .frontiers import Frontier, FrontierParams, find_frontiers, known_area

__all__ = ["Decision", "ExploreParams", "Explorer", "NO_MAP", "RETURN_FAILED"]

NO_MAP = 1
"""ExploreResult.error_code: no map or no robot pose came in time."""
RETURN_FAILED = 2
"""ExploreResult.error_code: exploring is done but the robot could not drive back."""


@dataclass(frozen=True)
class ExploreParams:
    frontiers: FrontierParams = field(default_factory=FrontierParams)
    progress_timeout: float = 30.0
    progress_distance: float = 0.1
    same_goal_radius: float = 0.5
    blacklist_radius: float = 0.5
    return_to_start: bool = True
    confirm_steps: int = 3
    """Planning steps in a row that must find no frontier before exploring ends: a mapper's
    correction can cut the robot's surroundings off for a moment."""
    far_start: float = 3.0
    """Times ``frontiers.start_radius`` the free space round the robot may be once goals
    were driven to (`Explorer.frontiers`)."""
    confirm_maps: int = 2
    """Maps (distinct grids) those steps must span: a mapper rebuilds its grid every few
    seconds (slam's ``map_update_interval``, 5 s), so the scans of the sweep just made are
    only in the next one; steps on one stale grid would end exploring early."""


Stage = Literal["exploring", "returning", "done"]


@dataclass
class Decision:
    """What the node does now: ``goto`` a new goal (``target``), ``keep`` driving to the
    current one, ``home`` (drive to the start pose), ``done`` (nothing left), ``wait`` (the
    map does not show the robot's surroundings yet: turn round to let the mapper see)."""

    action: Literal["goto", "keep", "home", "done", "wait"]
    target: Pose2 | None = None
    frontiers_left: int = 0


class Explorer:
    """The state of one exploration (one ``explore`` goal)."""

    def __init__(self, params: ExploreParams, start: Pose2) -> None:
        self.p = params
        self.start = start
        self.stage: Stage = "exploring"
        self.target: Pose2 | None = None
        self.blacklist: list[tuple[float, float]] = []
        self.goals_reached = 0
        self.goals_failed = 0
        self.explored_area = 0.0
        self.frontiers_left = 0
        self.return_ok = False
        self.empty_steps = 0
        self._empty_maps: list[GridMap] = []  # the grids of those steps, each once
        self._best = math.inf
        self._last_progress = 0.0

    # ------------------------------------------------------------------ planning

    def frontiers(self, grid: GridMap, robot: Pose2) -> list[Frontier] | None:
        """The frontiers with a goal away from the blacklisted ones, cheapest first; None
        while the map does not show free space round the robot. Once goals were driven to,
        free space up to ``far_start`` times further counts as round the robot: the map is
        there, only the spot the robot stands on is drawn badly (cells left unknown between
        a few scans' rays), and nav plans from where the robot is."""
        find = partial(find_frontiers, grid.grid, grid.resolution,
                       (grid.origin[0], grid.origin[1]), (robot.x, robot.y),
                       avoid=self.blacklist, avoid_radius=self.p.blacklist_radius)
        found = find(self.p.frontiers)
        if found is None and self.goals_reached + self.goals_failed > 0:
            f = self.p.frontiers
            found = find(replace(f, start_radius=f.start_radius * self.p.far_start))
        return found

    def step(self, grid: GridMap, robot: Pose2, now: float) -> Decision:
        """The decision at ``now`` (seconds) for the map ``grid`` and the robot at ``robot``."""
        self.explored_area = known_area(grid.grid, grid.resolution)
        if self.stage != "exploring":
            return Decision("keep" if self.stage == "returning" else "done", self.target)
        found = self.frontiers(grid, robot)
        if found is None:
            return Decision("wait", self.target)
        self.frontiers_left = len(found)
        self.empty_steps = self.empty_steps + 1 if not found else 0
        if found:
            self._empty_maps.clear()
        elif not any(g is grid for g in self._empty_maps):
            self._empty_maps.append(grid)
        if not found and (self.empty_steps < self.p.confirm_steps
                          or len(self._empty_maps) < self.p.confirm_maps):
            return Decision("wait", self.target)
        if not found:
            if self.target is not None:
                self.goals_reached += 1  # overtaken: the last frontier was mapped on the way
            return self.end_here()
        best = found[0]
        gx, gy = best.goal
        dist = math.hypot(gx - robot.x, gy - robot.y)
        cur = self.target
        same = cur is not None and math.hypot(cur.x - gx, cur.y - gy) <= self.p.same_goal_radius
        if not same or dist < self._best - self.p.progress_distance:
            self._last_progress = now
            self._best = dist if not same else min(self._best, dist)
        if same and now - self._last_progress > self.p.progress_timeout:
            assert cur is not None
            self.fail(cur)  # no progress: blacklisted; the next step picks another one
            return self.step(grid, robot, now)
        if same:
            return Decision("keep", cur, len(found))
        if cur is not None:
            self.goals_reached += 1  # overtaken: its frontier was mapped (or moved) on the way
        heading = math.atan2(gy - robot.y, gx - robot.x)
        self.target = Pose2(gx, gy, heading)
        self._best, self._last_progress = dist, now
        return Decision("goto", self.target, len(found))

    def end_here(self) -> Decision:
        """Exploring ends where it stands (the map round the robot cannot be planned from):
        back to the start, or done."""
        self.target = None
        if self.p.return_to_start:
            self.stage = "returning"
            self.target = self.start
            return Decision("home", self.start)
        self.stage = "done"
        return Decision("done")

    # ------------------------------------------------------------------ outcomes

    def reached(self, target: Pose2) -> None:
        """Nav reached ``target``: counted, and not a goal again."""
        self.goals_reached += 1
        self._forget(target)

    def fail(self, target: Pose2) -> None:
        """Nav aborted ``target`` (or it made no progress): blacklisted."""
        self.goals_failed += 1
        self._forget(target)

    def _forget(self, target: Pose2) -> None:
        self.blacklist.append((target.x, target.y))
        if self.target is not None and self.target == target:
            self.target = None
            self._best = math.inf

    def returned(self, ok: bool) -> None:
        """The drive back to the start ended (``ok``: reached)."""
        self.stage = "done"
        self.target = None
        self.return_ok = ok
