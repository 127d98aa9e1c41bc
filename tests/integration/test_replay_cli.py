"""`zenros replay`: two runs of one bag write the same bytes; --compare says identical, or
names the first differing message and exits 1; bad arguments get a clear error."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

# three replay processes a test, each importing nav: 6 s alone, over a minute on a loaded box
pytestmark = pytest.mark.timeout(240)

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
BAG = SCENARIOS / "goal_around_obstacle.in.mcap"


def zenros(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", *args], capture_output=True,
                          check=False, text=True, timeout=200, cwd=cwd)


@pytest.fixture
def maps(tmp_path: Path) -> list[str]:
    shutil.copytree(SCENARIOS / "maps", tmp_path / "maps")
    return ["-p", f"nav:maps_dir:={tmp_path / 'maps'}",
            "-p", f"nav:map:={tmp_path / 'maps' / 'room' / 'room.yaml'}"]


def test_two_replays_are_byte_identical_and_compare_identical(tmp_path: Path,
                                                              maps: list[str]) -> None:
    for name in ("a", "b"):
        r = zenros("replay", str(BAG), "--nodes", "nav", "-o", f"{name}.mcap", *maps,
                   cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        assert f"written to {name}.mcap" in r.stdout and "x real time" in r.stdout
        assert "wall-clock" not in r.stderr
    assert (tmp_path / "a.mcap").read_bytes() == (tmp_path / "b.mcap").read_bytes()
    r = zenros("replay", "--compare", "a.mcap", "b.mcap", cwd=tmp_path)
    assert (r.returncode, r.stdout.strip()) == (0, "identical")
    expected = SCENARIOS / "goal_around_obstacle.expected.mcap"
    assert (tmp_path / "a.mcap").read_bytes() == expected.read_bytes()


def test_a_changed_controller_gain_is_reported_at_the_first_cmd_vel(tmp_path: Path,
                                                                    maps: list[str]) -> None:
    gain = ["-p", "nav:lookahead_dist:=0.9"]
    r = zenros("replay", str(BAG), "--nodes", "nav", "-o", "g.mcap", *maps, *gain,
               cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    r = zenros("replay", "--compare", str(SCENARIOS / "goal_around_obstacle.expected.mcap"),
               "g.mcap", cwd=tmp_path)
    assert r.returncode == 1
    assert r.stdout.startswith("first difference at message ")
    assert "/cmd_vel at " in r.stdout and " != " in r.stdout


@pytest.mark.parametrize(("args", "error"), [
    (["replay", "nope.mcap", "--nodes", "nav", "-o", "o.mcap"], "no bag 'nope.mcap'"),
    (["replay", str(BAG), "--nodes", "navv", "-o", "o.mcap"], "no replayable service 'navv'"),
    (["replay", str(BAG), "-o", "o.mcap"], "usage: zenros replay BAG --nodes"),
    (["replay", str(BAG), "--nodes", "nav", "-o", "o.mcap", "-p", "slam:x:=1"],
     "parameters for slam, which is not replayed"),
    (["replay", "--compare", "a.mcap", "b.mcap"], "no such bag: a.mcap"),
])
def test_bad_arguments_get_a_clear_error(tmp_path: Path, args: list[str], error: str) -> None:
    r = zenros(*args, cwd=tmp_path)
    assert r.returncode != 0
    assert error in r.stderr
    assert "Traceback" not in r.stderr


def test_a_bag_recorded_with_ros_replays_into_nav_identically(tmp_path: Path,
                                                              maps: list[str]) -> None:
    """A rosbag2 (SQLite3) bag written by rosbags' own writer (scripts/make_ros_bag.py),
    read through zenros.bag's reader: its odometry, scans and goal reach nav, twice the same."""
    pytest.importorskip("rosbags")
    root = Path(__file__).resolve().parents[2]
    made = subprocess.run([sys.executable, str(root / "scripts" / "make_ros_bag.py"),
                           str(tmp_path / "rosbag"), "--storage", "sqlite3", "-n", "20"],
                          capture_output=True, text=True, timeout=120, check=False)
    assert made.returncode == 0, made.stderr
    for name in ("r1", "r2"):
        r = zenros("replay", "rosbag", "--nodes", "nav", "-o", f"{name}.mcap", *maps,
                   cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        assert "41 inputs delivered" in r.stdout  # /odom and /scan each step, /goal_pose
    assert (tmp_path / "r1.mcap").read_bytes() == (tmp_path / "r2.mcap").read_bytes()
