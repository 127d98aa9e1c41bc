"""The chassis as a process at 10x: the CLI sees odom, scans and TF; bad settings exit 3."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from collections.abc import Iterator

import pytest
from zenros.testing import Proc

pytestmark = pytest.mark.system


def zenros(router: str, prefix: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "zenros.cli", *args, "-e", router, "--prefix", prefix],
        capture_output=True, text=True, timeout=40, check=False,
    )


@pytest.fixture
def chassis(router: str, prefix: str) -> Iterator[Proc]:
    proc = Proc([sys.executable, "-m", "zenros.services.chassis", "-e", router,
                 "--prefix", prefix, "-p", "speed:=10.0"])
    try:
        assert proc.wait_line("started", 20), proc.output
        yield proc
    finally:
        assert proc.stop() == 0, proc.output


def test_cli_sees_odom_scan_and_tf(chassis: Proc, router: str, prefix: str) -> None:
    r = zenros(router, prefix, "topic", "echo", "/odom", "--once", "--json", "--timeout", "20")
    assert r.returncode == 0, r.stderr
    odom = json.loads(r.stdout.splitlines()[0])
    assert odom["header"]["frame_id"] == "odom" and odom["child_frame_id"] == "base_link"
    r = zenros(router, prefix, "topic", "hz", "/scan", "--count", "2")
    assert r.returncode == 0, r.stderr
    rates = [float(x) for x in re.findall(r"average rate: ([0-9.]+)", r.stdout)]
    assert rates and rates[-1] > 20  # 10 Hz of sim time at up to 10x
    r = zenros(router, prefix, "tf", "echo", "odom", "laser", "--once", "--timeout", "20")
    assert r.returncode == 0, r.stderr
    assert "Translation: [0.100, 0.000, 0.200]" in r.stdout
    assert "speed 10x, /clock on" in chassis.output


def test_faster_than_real_time_without_clock_is_refused(router: str, prefix: str) -> None:
    proc = Proc([sys.executable, "-m", "zenros.services.chassis", "-e", router,
                 "--prefix", prefix, "-p", "speed:=3.0", "-p", "publish_clock:=false"])
    try:
        assert proc.wait(30) == 3
        assert "publish_clock is false" in proc.output
    finally:
        proc.stop()
