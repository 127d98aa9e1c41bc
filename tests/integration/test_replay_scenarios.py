"""Scenario tests from bags (zenros.replay.scenario): nav replayed on a recorded input bag
must give the expected output bag, message for message (docs/replay.md). The bags are made
by tests/scenarios/make_bags.py."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from zenros.replay.scenario import Scenario, ScenarioFailed

HERE = Path(__file__).resolve().parents[1] / "scenarios"


def scenario(name: str, tmp_path: Path, **nav: object) -> Scenario:
    maps = tmp_path / "maps"
    shutil.copytree(HERE / "maps", maps)  # nav may write into its store: never the repo's
    params = {"maps_dir": str(maps), "map": str(maps / "room" / "room.yaml"), **nav}
    return Scenario(HERE / f"{name}.in.mcap", HERE / f"{name}.expected.mcap", ["nav"],
                    {"nav": params})


def test_a_goal_around_an_obstacle(tmp_path: Path) -> None:
    res = scenario("goal_around_obstacle", tmp_path).check(tmp_path)
    assert res.delivered > 900 and res.recorded > 1000


def test_a_patrol_through_two_nav_points(tmp_path: Path) -> None:
    res = scenario("patrol", tmp_path).check(tmp_path)
    assert res.delivered > 1000


def test_a_changed_gain_fails_the_scenario_at_the_first_cmd_vel_it_changes(
        tmp_path: Path) -> None:
    with pytest.raises(ScenarioFailed, match=r"/cmd_vel at [0-9.]+ s, \.(linear|angular)"):
        scenario("goal_around_obstacle", tmp_path, lookahead_dist=0.9).check(tmp_path)
