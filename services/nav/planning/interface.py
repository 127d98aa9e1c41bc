"""`Planner`: a global planner plugin, Nav2's ``nav2_core::GlobalPlanner`` shape.

A plugin plans one leg, ``create_plan(costmap, start, goal)``, on a costmap snapshot and
returns the path's points; it raises a `PlanningError` (ComputePathToPose's code) when it
cannot, as Nav2's plugins throw ``nav2_core::PlannerException``s. `GlobalPlanner` (the
planner server) picks the plugin by id, runs it leg by leg through the requested poses and
joins the legs. Plugins are classes (`PlannerPlugin`) with their own parameters (one msgspec
Struct, declared as ``<id>.<field>``), listed by type name in `registry.PLANNERS`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, Generic, Protocol, TypeVar

import msgspec
import numpy as np
from zenros.se2 import Pose2

from ..costmap.snapshot import CostSnapshot
from .plan import PlannerParams

__all__ = ["NoParameters", "Planner", "PlannerContext", "PlannerPlugin"]

P = TypeVar("P", bound=msgspec.Struct)


class Planner(Protocol):
    """What the planner server asks of a plugin."""

    def create_plan(self, costmap: CostSnapshot, start: Pose2, goal: Pose2) -> np.ndarray:
        """An (N, 2) path in ``map`` from ``start`` to ``goal`` (N >= 1).

        Raises:
            PlanningError: no plan (its ``code`` is ComputePathToPose's: 203-208).
        """
        ...


class NoParameters(msgspec.Struct, frozen=True):
    """The parameters of a plugin that has none of its own."""


@dataclass(frozen=True)
class PlannerContext:
    """What every plugin is built with: nav's planner parameters (``cost_travel_multiplier``,
    ``allow_unknown``, ``max_planning_time`` as `PlannerParams`), the robot's radius and
    ``planner_tolerance`` (m)."""

    search: PlannerParams = field(default_factory=PlannerParams)
    robot_radius: float = 0.22
    goal_tolerance: float = 0.25


class PlannerPlugin(Generic[P]):
    """Base of the planner plugins: ``Parameters`` (a frozen msgspec Struct, its fields the
    plugin's parameters), built with them and the `PlannerContext`."""

    Parameters: ClassVar[type[msgspec.Struct]] = NoParameters

    def __init__(self, params: P, context: PlannerContext) -> None:
        self.params = params
        self.context = context

    def create_plan(self, costmap: CostSnapshot, start: Pose2, goal: Pose2) -> np.ndarray:
        raise NotImplementedError


AnyPlugin = PlannerPlugin[Any]
