"""The planner plugins, registered in one place: `PLANNERS` (type name -> class).

Nav2's shape: the parameter ``planner_plugins`` lists planner ids; each id's ``<id>.plugin``
names its type here (ids in `DEFAULT_TYPES` have a default), its other parameters are the
type's ``Parameters`` as ``<id>.<field>``. A new planner is one module in this package and
one line below (docs/nav-planner.md, Adding a planner).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import msgspec

from .area_coverage import CoveragePlanner
from .grid_based import AStarPlanner
from .interface import AnyPlugin, NoParameters, Planner, PlannerContext

__all__ = ["DEFAULT_PLANNERS", "DEFAULT_TYPES", "PLANNERS", "PlannerSpec", "build_planners",
           "check_names", "default_specs", "plugin_type"]

PLANNERS: dict[str, type[AnyPlugin]] = {
    "zenros_nav/AStarPlanner": AStarPlanner,
    "zenros_nav/CoveragePlanner": CoveragePlanner,
}

DEFAULT_TYPES: dict[str, str] = {
    "GridBased": "zenros_nav/AStarPlanner",
    "Coverage": "zenros_nav/CoveragePlanner",
}
"""The plugin type of an id whose ``<id>.plugin`` is not set."""

DEFAULT_PLANNERS: tuple[str, ...] = ("GridBased", "Coverage")
"""``planner_plugins``' default; the first is the one navigation uses."""


@dataclass(frozen=True)
class PlannerSpec:
    """One planner id: its plugin type and its parameters."""

    name: str
    plugin: str
    params: msgspec.Struct = field(default_factory=NoParameters)


def plugin_type(name: str, plugin: str) -> type[AnyPlugin]:
    """The class ``plugin`` names for planner ``name``.

    Raises:
        ValueError: an unknown type or none (the message lists the known ones).
    """
    known = ", ".join(sorted(PLANNERS))
    if not plugin:
        raise ValueError(f"planner {name!r}: parameter '{name}.plugin' is not set; "
                         f"known plugin types: {known}")
    if plugin not in PLANNERS:
        raise ValueError(f"planner {name!r}: unknown plugin type {plugin!r} "
                         f"(parameter '{name}.plugin'); known plugin types: {known}")
    return PLANNERS[plugin]


def default_specs() -> tuple[PlannerSpec, ...]:
    """The planners nav runs with no planner parameters set."""
    return tuple(PlannerSpec(n, DEFAULT_TYPES[n], PLANNERS[DEFAULT_TYPES[n]].Parameters())
                 for n in DEFAULT_PLANNERS)


def check_names(names: Sequence[str]) -> None:
    """Raises ValueError: no planner id, an empty one or one twice."""
    if not names:
        raise ValueError("parameter 'planner_plugins': at least one planner id")
    for n in names:
        if not n or "." in n or names.count(n) > 1:
            raise ValueError(f"parameter 'planner_plugins': {n!r} is empty, has a '.' or "
                             "is listed twice")


def build_planners(specs: Sequence[PlannerSpec], context: PlannerContext
                   ) -> Mapping[str, Planner]:
    """Each spec's plugin built with its parameters, by id, in order."""
    built: dict[str, Any] = {}
    for spec in specs:
        built[spec.name] = plugin_type(spec.name, spec.plugin)(spec.params, context)
    return built
