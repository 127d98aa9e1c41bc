"""`zenros bag info` and `zenros bag play` on a rosbag2 MCAP bag recorded as ROS records it,
as real processes: the play reaches a zenros subscriber with the recorded values in order."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from ros_bags import make
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import Collector

pytestmark = pytest.mark.system
pytest.importorskip("rosbags", reason="rosbags not installed (pip install -e '.[rosbags]')")

N = 10


def zenros(*args: str, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", *args], capture_output=True,
                          text=True, timeout=timeout, check=False)


def inproc(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    """A verb that needs no network (info), run in this process: the console script's code
    without a process start each time."""
    from zenros.cli.__main__ import main

    capsys.readouterr()
    rc = main(list(args))
    out, err = capsys.readouterr()
    return rc, out, err


def test_info_and_play_a_rosbag2_mcap_bag(router: str, prefix: str, tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    bag = make(tmp_path, "mcap", N, unknown=True)
    rc, out, err = inproc(capsys, "bag", "info", str(bag))
    assert rc == 0, err
    assert "Storage id:        mcap (recorded with ROS)" in out
    assert "Topic: /cmd_vel   | Type: geometry_msgs/msg/Twist | Count: 10" in out
    assert "NOT PLAYED: zenros has no type my_robot_msgs/msg/Battery" in out
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    node = Node("ros_bag_listener", context=ctx)
    got: Collector[Twist] = Collector()
    try:
        node.create_subscription(Twist, "/cmd_vel", got)
        r = zenros("bag", "play", str(bag), "--rate", "4", "-e", router, "--prefix", prefix)
        assert r.returncode == 0, r.stdout + r.stderr
        assert f"Played {4 * N + 2} messages" in r.stdout
        warned = [ln for ln in r.stderr.splitlines() if "/custom" in ln]  # one warning
        assert len(warned) == 1, r.stderr
        assert "not played: zenros has no type my_robot_msgs/msg/Battery" in warned[0]
        assert got.wait(N, 10), len(got)
    finally:
        node.close()
        ctx.close()
    assert [m.linear.x for m in got.items] == pytest.approx([0.1 * i for i in range(N)])


def test_a_corrupt_bag_is_one_clear_line(tmp_path: Path) -> None:
    bad = tmp_path / "broken.db3"
    bad.write_bytes(b"SQLite format 3\x00" + b"\x07" * 2048)
    r = zenros("bag", "play", str(bad))  # one real process: the console script's exit code
    assert r.returncode == 1, r.stdout + r.stderr
    assert "broken.db3: not a readable ROS bag" in r.stderr
    assert "Traceback" not in r.stderr
