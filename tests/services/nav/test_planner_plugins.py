"""Planner plugins (Nav2's planner_plugins): chosen by id, their types and parameters declared
at start, bad names refused with the known ones, a new plugin one class and one line."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from test_planning import room
from zenros.errors import InvalidParameterValueError
from zenros.maps import GridMap
from zenros.msgs.nav2_msgs import ComputePathToPoseResult as Codes
from zenros.params import Parameters
from zenros.se2 import Pose2
from zenros.services.nav.core import NavConfig
from zenros.services.nav.costmap import CostmapParams
from zenros.services.nav.costmap.live import Costmaps
from zenros.services.nav.costmap.snapshot import CostSnapshot
from zenros.services.nav.params import NavParameters, nav_config, planner_specs
from zenros.services.nav.planning import PlannerParams, registry
from zenros.services.nav.planning.area_coverage import CoverageParameters
from zenros.services.nav.planning.global_planner import GlobalPlanner
from zenros.services.nav.planning.interface import NoParameters, PlannerContext, PlannerPlugin
from zenros.services.nav.planning.registry import PlannerSpec, build_planners

KNOWN = "known plugin types: zenros_nav/AStarPlanner, zenros_nav/CoveragePlanner"


def server(specs: tuple[PlannerSpec, ...]) -> GlobalPlanner:
    context = PlannerContext(PlannerParams(), 0.2, 0.25)
    return GlobalPlanner(PlannerParams(), 0.2, 0.25, build_planners(specs, context))


def test_the_default_planners_are_the_grid_one_then_coverage() -> None:
    assert [(s.name, s.plugin) for s in NavConfig().planners] == [
        ("GridBased", "zenros_nav/AStarPlanner"), ("Coverage", "zenros_nav/CoveragePlanner")]
    params = Parameters("/nav")
    assert nav_config(NavParameters(), params) == NavConfig()
    assert params.get("GridBased.plugin") == "zenros_nav/AStarPlanner"
    assert params.get("Coverage.op_width") == 0.4


def test_ids_types_and_plugin_parameters_come_from_the_parameters() -> None:
    params = Parameters("/nav", {"Fast.plugin": "zenros_nav/AStarPlanner",
                                 "Mow.plugin": "zenros_nav/CoveragePlanner",
                                 "Mow.op_width": 0.8, "Mow.swath_angle": 90.0})
    specs = planner_specs(["Fast", "Mow"], params)
    assert specs == (PlannerSpec("Fast", "zenros_nav/AStarPlanner", NoParameters()),
                     PlannerSpec("Mow", "zenros_nav/CoveragePlanner",
                                 CoverageParameters(op_width=0.8, swath_angle=90.0)))
    assert {p.name: p.read_only for p in params.describe()}["Mow.op_width"]
    assert server(specs).ids == ["Fast", "Mow"]  # the first is the default


@pytest.mark.parametrize(("names", "values", "match"), [
    (["Foo"], {}, f"planner 'Foo': parameter 'Foo.plugin' is not set; {KNOWN}"),
    (["GridBased"], {"GridBased.plugin": "nav2_navfn_planner/NavfnPlanner"},
     f"unknown plugin type 'nav2_navfn_planner/NavfnPlanner' .*; {KNOWN}"),
    ([], {}, "at least one planner id"),
    (["GridBased", "GridBased"], {}, "listed twice"),
    (["Coverage"], {"Coverage.op_width": -1.0}, "parameter 'Coverage.op_width'"),
])
def test_bad_planners_fail_at_start_naming_the_known_ones(
        names: list[str], values: dict[str, object], match: str) -> None:
    with pytest.raises(InvalidParameterValueError, match=match):
        nav_config(NavParameters(planner_plugins=names), Parameters("/nav", values))


def test_planner_id_selects_the_plugin_and_an_unknown_one_is_refused() -> None:
    planner = server(registry.default_specs())
    snap = room().snapshot()
    start, goal = Pose2(1.0, 1.0), Pose2(3.0, 2.5)
    grid = planner.plan(snap, start, [goal])
    assert planner.plan(snap, start, [goal], "GridBased").xy == pytest.approx(grid.xy)
    mow = planner.plan(snap, start, [goal], "Coverage")
    assert grid.ok and mow.ok and grid.xy is not None and mow.xy is not None
    assert mow.xy[0] == pytest.approx([1.0, 1.0]) and mow.xy[-1] == pytest.approx([3.0, 2.5])
    assert mow.leg_ends[-1] > 4 * grid.leg_ends[-1]  # back and forth over the area
    bad = planner.plan(snap, start, [goal], "Smac")
    assert (bad.error_code, bad.error_msg) == (
        Codes.INVALID_PLANNER, "unknown planner_id 'Smac'; this server has GridBased, Coverage")


def test_coverage_sweeps_the_area_and_goes_round_what_stands_in_it() -> None:
    g = np.zeros((120, 200), dtype=np.int8)
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = 100
    g[35:37, 40:47] = 100  # a bench in the area, (2.0, 1.75) to (2.35, 1.85)
    cm = Costmaps(CostmapParams(robot_radius=0.2, inflation_radius=0.5, cost_scaling_factor=3.0))
    cm.set_map(GridMap(g, 0.05, (0.0, 0.0, 0.0)))
    snap = cm.snapshot()
    planner = server((PlannerSpec("Coverage", "zenros_nav/CoveragePlanner",
                                  CoverageParameters(op_width=0.5)),))
    out = planner.plan(snap, Pose2(1.0, 1.0), [Pose2(4.0, 3.0)])
    assert out.ok and out.xy is not None, out.error_msg
    cells = [snap.world_to_map(x, y) for x, y in out.xy]
    assert all(c is not None and snap.costs[c[1], c[0]] < 253 for c in cells[1:-1])
    # every free point of the area is within a swath's half width (plus a cell) of the path
    for x in np.linspace(1.3, 3.7, 9):
        for y in np.linspace(1.3, 2.7, 5):
            c = snap.world_to_map(x, y)
            assert c is not None
            if snap.costs[c[1], c[0]] < 128:
                near = np.min(np.hypot(out.xy[:, 0] - x, out.xy[:, 1] - y))
                assert near <= 0.25 + 0.1, (x, y, near)


def test_coverage_of_no_area_fails_with_no_valid_path() -> None:
    planner = server(registry.default_specs())
    out = planner.plan(room().snapshot(), Pose2(1.0, 1.0), [Pose2(3.0, 1.0)], "Coverage")
    assert out.error_code == Codes.NO_VALID_PATH and "no coverage" in out.error_msg


class Straight(PlannerPlugin[NoParameters]):
    """A planner that is not in the registry: a straight line, or a bug on request."""

    def create_plan(self, costmap: CostSnapshot, start: Pose2, goal: Pose2) -> np.ndarray:
        if goal.y > 5:
            raise ZeroDivisionError("a bug")
        return np.array([[start.x, start.y], [goal.x, goal.y]])


def test_a_new_planner_is_one_class_and_one_registry_line(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(registry.PLANNERS, "test/Straight", Straight)
    params = Parameters("/nav", {"Line.plugin": "test/Straight"})
    planner = server(planner_specs(["GridBased", "Line"], params))
    snap = room().snapshot()
    out = planner.plan(snap, Pose2(1.0, 1.0), [Pose2(8.0, 1.0), Pose2(8.0, 2.0)], "Line")
    assert out.xy is not None and out.xy.tolist() == [[1.0, 1.0], [8.0, 1.0], [8.0, 2.0]]
    assert out.leg_ends == pytest.approx([7.0, 8.0])
    broken = planner.plan(snap, Pose2(1.0, 1.0), [Pose2(8.0, 5.5)], "Line")
    assert broken.error_code == Codes.UNKNOWN and "'Line' failed: ZeroDivisionError" in \
        broken.error_msg
    assert planner.plan(snap, Pose2(1.0, 1.0), [Pose2(8.0, 1.0)]).xy is not None  # GridBased


def test_the_documented_planner_is_one_module_and_one_registry_line(
        monkeypatch: pytest.MonkeyPatch, doc_module: Callable[[str, str], Any]) -> None:
    """The straight planner of docs/nav-planner.md's "Adding a planner", as written there."""
    plugin = doc_module("nav-planner.md", "# services/nav/planning/straight.py").StraightPlanner
    monkeypatch.setitem(registry.PLANNERS, "zenros_nav/StraightPlanner", plugin)
    params = Parameters("/nav", {"Straight.plugin": "zenros_nav/StraightPlanner"})
    planner = server(planner_specs(["GridBased", "Straight"], params))
    snap = room().snapshot()
    out = planner.plan(snap, Pose2(1.0, 1.0), [Pose2(4.0, 1.0)], "Straight")
    assert out.xy is not None and len(out.xy) == 60 and out.leg_ends == pytest.approx([3.0])
    through = planner.plan(snap, Pose2(1.0, 1.0), [Pose2(8.0, 1.0)], "Straight")
    assert through.error_code == Codes.NO_VALID_PATH and "blocked" in through.error_msg
