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


def test_slam_maps_the_patrol_the_same_way_twice(tmp_path: Path) -> None:
    """slam alone (``start_mapping``) on the patrol's odometry and scans: it folds scans in
    the callback, so two replays give the same map, poses and map -> odom."""
    from zenros.bag.reader import bag_files, iter_messages
    from zenros.replay import compare_bags, replay_bag

    params = {"slam": {"start_mapping": True}}
    a = replay_bag(HERE / "patrol.in.mcap", ["slam"], tmp_path / "a.mcap", params=params)
    b = replay_bag(HERE / "patrol.in.mcap", ["slam"], tmp_path / "b.mcap", params=params)
    assert a.wall_reads == [] and compare_bags(a.output, b.output) is None
    assert a.output.read_bytes() == b.output.read_bytes()
    topics = {m.channel.topic for m in iter_messages(bag_files(a.output))}
    assert {"/map", "/slam/pose", "/slam/track", "/tf"} <= topics
