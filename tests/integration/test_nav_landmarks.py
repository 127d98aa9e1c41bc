"""Landmarks on the simulated robot (chassis at 10x, nav, gateway): the laser's strong
returns on the office's reflectors, nav's relocalisation on them after a wrong initial pose,
and ``GET /navigation/landmarks``."""

from __future__ import annotations

import math
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest
from sim_robot import GatewayRobot, gateway_robot
from zenros.maps import load_landmarks
from zenros.msgs.geometry_msgs import Pose2D
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.zenros_msgs import (
    ImportMap,
    ImportMapRequest,
    LandmarkDetections,
    RelocalizeLandmarks,
    RelocalizeLandmarksRequest,
    Teleport,
    TeleportRequest,
)
from zenros.se2 import Pose2, angle_diff
from zenros.services.chassis.reflectors import STRONG
from zenros.services.nav.params import DEMO_MAP
from zenros.testing import wait_for
from zenros.tf import yaw_from_msg


@pytest.fixture(scope="module")
def robot(tmp_path_factory: pytest.TempPathFactory) -> Iterator[GatewayRobot]:
    with gateway_robot(tmp_path_factory.mktemp("landmarks")) as r:
        yield r


class Truth:
    """The last ground truth (pose and stamp in ns) the chassis published."""

    def __init__(self, robot: GatewayRobot) -> None:
        self.pose: Pose2 | None = None
        self.stamp = 0
        robot.user.create_subscription(Odometry, "sim/ground_truth", self._on)

    def _on(self, msg: Odometry) -> None:
        p = msg.pose.pose
        self.pose = Pose2(p.position.x, p.position.y, yaw_from_msg(p.orientation))
        self.stamp = msg.header.stamp.nanoseconds


def test_the_scan_is_strong_on_reflectors(robot: GatewayRobot) -> None:
    scans: list[LaserScan] = []
    seen: list[LandmarkDetections] = []
    robot.user.create_subscription(LaserScan, "scan", scans.append)
    robot.user.create_subscription(LandmarkDetections, "landmarks/detections", seen.append)
    assert wait_for(lambda: bool(scans) and bool(seen), 10)
    scan = scans[-1]
    assert len(scan.intensities) == len(scan.ranges)
    assert max(scan.intensities) >= STRONG and min(scan.intensities) >= 0
    assert wait_for(lambda: len(seen[-1].points) >= 2, 10)
    assert seen[-1].header.frame_id == "base_link"


def test_relocalises_after_a_wrong_initial_pose(robot: GatewayRobot) -> None:
    """The robot at (6, 0.3) facing 0.5 rad; nav told it is 1 m and 20 degrees off; one
    call puts the estimate within 5 cm and 2 degrees of the truth."""
    truth = Truth(robot)
    teleport = robot.user.create_client(Teleport, "sim/teleport")
    reloc = robot.user.create_client(RelocalizeLandmarks, "relocalize_landmarks")
    try:
        assert teleport.call(TeleportRequest(pose=Pose2D(x=6.0, y=0.3, theta=0.5)),
                             timeout=10).success
        assert wait_for(lambda: truth.pose is not None
                        and truth.pose.distance(Pose2(6.0, 0.3, 0.5)) < 1e-6, 10)
        since = truth.stamp
        # a scan cast at the new pose has reached nav
        assert wait_for(lambda: (s := robot.nav.landmarks._scan) is not None
                        and s.header.stamp.nanoseconds > since, 10)
        wrong = Pose2(6.0 + 0.8, 0.3 - 0.6, 0.5 + math.radians(20))
        r = robot.http.post("/navigation/init_pose", json={"x": wrong.x, "y": wrong.y,
                                                           "z": wrong.theta})
        assert r.status_code == 200, r.text
        assert wait_for(lambda: (p := robot.nav.core.localizer.pose()) is not None
                        and p.distance(wrong) < 0.01, 10)
        res = reloc.call(RelocalizeLandmarksRequest(), timeout=10)
        assert res.success, res.message
        assert res.matched >= 2 and res.detected >= res.matched and res.map_name == "office"
        assert res.shift == pytest.approx(1.0, abs=0.06)
        est = robot.nav.core.localizer.pose()
        assert est is not None and truth.pose is not None
        assert est.distance(truth.pose) < 0.05, (est, truth.pose)
        assert abs(math.degrees(angle_diff(est.theta, truth.pose.theta))) < 2.0
    finally:
        robot.nav.core.set_localization("ground_truth")
        assert teleport.call(TeleportRequest(pose=Pose2D()), timeout=10).success


def test_relocalising_without_reflectors_in_view_is_refused(robot: GatewayRobot) -> None:
    """In the first north office, away from its door, the scan shows no reflector: a clear
    refusal, the estimate untouched."""
    teleport = robot.user.create_client(Teleport, "sim/teleport")
    reloc = robot.user.create_client(RelocalizeLandmarks, "relocalize_landmarks")
    try:
        assert teleport.call(TeleportRequest(pose=Pose2D(x=3.0, y=7.0)), timeout=10).success
        assert wait_for(lambda: (s := robot.nav.landmarks._scan) is not None
                        and len(robot.nav.landmarks.detect(s)) == 0
                        and robot.nav.core.localizer.pose() is not None
                        and robot.nav.core.localizer.pose().distance(Pose2(3.0, 7.0)) < 0.05,
                        10)
        before = robot.nav.core.localizer.pose()
        res = reloc.call(RelocalizeLandmarksRequest(), timeout=10)
        assert not res.success and "the scan shows 0 reflector(s)" in res.message
        assert robot.nav.core.localizer.pose() == before
    finally:
        assert teleport.call(TeleportRequest(pose=Pose2D()), timeout=10).success


def test_get_landmarks(robot: GatewayRobot, tmp_path: Path) -> None:
    marks = load_landmarks(DEMO_MAP)
    r = robot.http.get("/navigation/landmarks", params={"map_name": "office"})
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["map_name"] == "office"
    assert body["landmarks"] == [{"id": m.id, "x": m.x, "y": m.y, "theta": 0.0,
                                  "radius": m.radius} for m in marks]
    assert robot.http.get("/navigation/landmarks").json() == body  # the current map
    r = robot.http.get("/navigation/landmarks", params={"map_name": "nowhere"})
    assert r.status_code == 404 and "unknown map 'nowhere'" in r.json()["description"]
    r = robot.http.get("/navigation/landmarks", params={"map_name": "../x"})
    assert r.status_code == 400
    # a map without a landmarks.yaml has none
    for name in ("office.yaml", "office.pgm"):
        shutil.copy(Path(DEMO_MAP).parent / name, tmp_path / name.replace("office", "bare"))
    (tmp_path / "bare.yaml").write_text(
        (tmp_path / "bare.yaml").read_text().replace("office.pgm", "bare.pgm"))
    imp = robot.user.create_client(ImportMap, "map_server/import_map")
    assert imp.call(ImportMapRequest(name="bare", yaml_path=str(tmp_path / "bare.yaml")),
                    timeout=10).info.name == "bare"
    r = robot.http.get("/navigation/landmarks", params={"map_name": "bare"})
    assert r.status_code == 200 and r.json() == {"map_name": "bare", "landmarks": []}
