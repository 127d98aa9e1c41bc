"""The mapping session: odometry looked up at each scan's stamp, scans folded on the worker,
bad scans refused without stopping it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from slam_worlds import ROOM, cast
from zenros.se2 import Pose2
from zenros.services.slam.mapper import ScanOutcome
from zenros.services.slam.params import SlamParameters
from zenros.services.slam.session import MappingSession, OdomBuffer


def test_odometry_is_interpolated_at_the_scan_stamp() -> None:
    buf = OdomBuffer()
    buf.add(1.0, Pose2(0.0, 0.0, 0.0))
    buf.add(1.1, Pose2(0.1, 0.0, 0.2))
    p = buf.at(1.05)
    assert p is not None and p.x == pytest.approx(0.05) and p.theta == pytest.approx(0.1)
    assert buf.at(0.5) is None  # older than anything kept
    assert buf.at(1.2) == Pose2(0.1, 0.0, 0.2)  # a little newer: the last one
    assert buf.at(3.0) is None  # far newer: unknown
    buf.add(0.2, Pose2(5.0, 0.0, 0.0))  # time went back: start over
    assert buf.at(1.05) is None and buf.at(0.2) == Pose2(5.0, 0.0, 0.0)


def test_scans_are_folded_on_the_worker() -> None:
    folded: list[ScanOutcome] = []
    session = MappingSession(SlamParameters(laser_x=0.0), lambda out, t: folded.append(out))
    try:
        scan = cast(ROOM, Pose2(2.0, 1.5, 0.0))
        assert not session.on_scan(0.0, scan.ranges, -math.pi, 2 * math.pi / 360, 0.05, 12.0)
        session.begin()
        for k in range(6):
            t = 0.1 * k
            truth = Pose2(2.0 + 0.6 * k, 1.5, 0.0)
            session.on_odom(t, Pose2(0.6 * k, 0.0, 0.0))
            r = cast(ROOM, truth).ranges
            assert session.on_scan(t, r, -math.pi, 2 * math.pi / 360, 0.05, 12.0)
        assert session.worker.wait_idle(30)
        assert len(folded) == 6 and session.counts()[1] == 6
        pose, m2o, stamp = session.pose()
        assert math.hypot(pose.x - 3.0, pose.y) < 0.05 and stamp == pytest.approx(0.5)
        # a small move is folded at once by odometry alone (no node, not queued)
        session.on_odom(0.6, Pose2(3.1, 0.0, 0.0))
        assert session.on_scan(0.6, r, -math.pi, 2 * math.pi / 360, 0.05, 12.0)
        assert folded[-1].node is None and session.counts()[1] == 6
        assert session.pose()[0].x == pytest.approx(3.1, abs=0.05)
        snap = session.snapshot()
        assert snap is not None and (snap.cells == 100).sum() > 100
        with pytest.raises(ValueError):
            session.on_scan(0.6, np.array([], np.float32), 0.0, 0.1, 0.05, 12.0)
        session.end()
        assert not session.on_scan(0.7, r, -math.pi, 2 * math.pi / 360, 0.05, 12.0)
    finally:
        session.close()
