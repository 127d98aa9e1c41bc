"""A run recorded with ROS replays into zenros's nav (zenros.bag.foreign under
zenros.replay): the scenario input of tests/scenarios re-written as rosbag2 bags (SQLite3
and MCAP storage, CDR, as ``ros2 bag record`` stores them) replays deterministically, the
same from either storage and the same as from a zenros bag of the messages zenros read from
it, and nav drives the scenario as it does from the original."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from ros_bags import to_rosbag2, to_zenros_bag
from zenros.bag import bag_info
from zenros.replay.bagrun import replay_bag
from zenros.replay.compare import compare_bags

pytest.importorskip("rosbags", reason="rosbags not installed (pip install -e '.[rosbags]')")

HERE = Path(__file__).resolve().parents[1] / "scenarios"
SCENARIO = "goal_around_obstacle"


def test_a_rosbag2_recording_replays_into_nav(tmp_path: Path) -> None:
    maps = tmp_path / "maps"
    shutil.copytree(HERE / "maps", maps)  # nav may write into its store: never the repo's
    params = {"nav": {"maps_dir": str(maps), "map": str(maps / "room" / "room.yaml")}}
    original = HERE / f"{SCENARIO}.in.mcap"
    db3 = to_rosbag2(original, tmp_path / "ros_sqlite3", "sqlite3")
    mcap = to_rosbag2(original, tmp_path / "ros_mcap", "mcap")
    assert bag_info(db3).recorded_with_ros and bag_info(mcap).recorded_with_ros
    assert bag_info(db3).messages == bag_info(original).messages
    outs = {}
    for name, bag in (("sqlite3", db3), ("mcap", mcap),
                      ("zenros", to_zenros_bag(db3, tmp_path / "read_back.mcap"))):
        outs[name] = tmp_path / f"{name}.out.mcap"
        res = replay_bag(bag, ["nav"], outs[name], params=params)
        assert res.delivered > 900 and res.recorded > 1000 and not res.wall_reads
    assert compare_bags(outs["sqlite3"], outs["mcap"]) is None
    assert compare_bags(outs["sqlite3"], outs["zenros"]) is None
    # ROS stores LaserScan's angles as float32 (zenros's bag had them as float64): the
    # costmaps may differ in a cell, but nav drives the same run (the same topics and counts)
    expected, got = bag_info(HERE / f"{SCENARIO}.expected.mcap"), bag_info(outs["sqlite3"])
    assert {(t.topic, t.count) for t in got.topics} == {(t.topic, t.count) for t in expected.topics}
