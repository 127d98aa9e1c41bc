"""`replay_bag(..., clock_topic="/clock")`: a bag recorded live from a simulation, whose log
times are the recorder's wall clock, replays on the bag's /clock instead."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from zenros.bag.reader import BagError, bag_files, iter_messages
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.rosgraph_msgs import Clock
from zenros.replay.bagrun import replay_bag
from zenros.replay.outbag import OutputBag

ROOM = Path(__file__).resolve().parents[1] / "scenarios" / "maps"
WALL0 = 1_765_000_000 * 10**9  # the recorder's wall clock
SIM0 = 100 * 10**9  # the simulation's clock
MS = 1_000_000


def live_bag(path: Path, with_clock: bool = True) -> Path:
    """3 s of a sim at 2x: /clock every 10 ms of sim time (5 ms of wall), odometry every
    50 ms of sim time, logged 1 ms of wall after the clock message before it."""
    bag = OutputBag(path)
    for k in range(300):
        sim, wall = SIM0 + k * 10 * MS, WALL0 + k * 5 * MS
        if with_clock:
            bag.add("/clock", Clock(clock=Time.from_nanoseconds(sim)), wall)
        if k % 5 == 0:
            o = Odometry()
            o.header.stamp, o.header.frame_id = Time.from_nanoseconds(sim), "odom"
            o.pose.pose.orientation.w = 1.0
            bag.add("/odom", o, wall + MS)
            bag.add("/sim/ground_truth", o, wall + MS)
    bag.close()
    return path


@pytest.fixture
def nav(tmp_path: Path) -> dict[str, dict[str, str]]:
    shutil.copytree(ROOM, tmp_path / "maps")
    return {"nav": {"maps_dir": str(tmp_path / "maps"),
                    "map": str(tmp_path / "maps" / "room" / "room.yaml")}}


def test_the_clock_topic_sets_the_time(tmp_path: Path, nav: dict[str, dict[str, str]]) -> None:
    res = replay_bag(live_bag(tmp_path / "live.mcap"), ["nav"], tmp_path / "out.mcap",
                     params=nav, clock_topic="/clock")
    assert res.delivered == 120 and res.sim_seconds == pytest.approx(2.99)
    status = [m.log_time for m in iter_messages(bag_files(tmp_path / "out.mcap"))
              if m.channel.topic == "/nav/status"]
    # nav/status every 0.5 s of sim time after the first clock value, at exact times
    assert status == [SIM0 + k * 500 * MS for k in range(1, 6)]


def test_log_times_are_the_time_without_it(tmp_path: Path,
                                           nav: dict[str, dict[str, str]]) -> None:
    res = replay_bag(live_bag(tmp_path / "live.mcap"), ["nav"], tmp_path / "out.mcap",
                     params=nav)
    assert res.sim_seconds == pytest.approx(1.495)  # the wall time the recording took
    first = next(iter_messages(bag_files(tmp_path / "out.mcap")))
    assert first.log_time >= WALL0


def test_a_bag_without_the_clock_topic_is_refused(tmp_path: Path,
                                                  nav: dict[str, dict[str, str]]) -> None:
    with pytest.raises(BagError, match="no /clock messages"):
        replay_bag(live_bag(tmp_path / "live.mcap", with_clock=False), ["nav"],
                   tmp_path / "out.mcap", params=nav, clock_topic="/clock")
