"""The calibrations: the estimators on synthetic data (a gyro's bias, ICP, the laser's mount
from base and laser motions), and the device on the simulated robot: the IMU's bias measured
standing still and taken off its readings, the laser's mount error found by driving a turn
and a straight line and applied on complete; refusals with the reason."""

from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np
import pytest
from scipy.spatial import cKDTree
from test_chassis_actuators import build_device
from zenros.msgs.zenros_msgs import CalibrateRequest
from zenros.se2 import Pose2
from zenros.services.chassis.calibration import (
    ScanPair,
    gyro_bias,
    laser_mount,
    match_scans,
    normals,
    scan_points,
)
from zenros.services.chassis.devices import CalibrationDevice, CameraDevice, ImuDevice, LaserDevice
from zenros.services.chassis.obstacles import Obstacle
from zenros.testing import wait_for


def test_gyro_bias_is_the_mean_of_a_still_gyro() -> None:
    rng = np.random.default_rng(1)
    bias, err = gyro_bias(0.004 + rng.normal(0, 0.002, 1000))
    assert bias == pytest.approx(0.004, abs=3 * err) and err < 1e-4
    with pytest.raises(ValueError, match="two samples"):
        gyro_bias([0.1])


def _room_points(pose: Pose2, rng: np.random.Generator) -> np.ndarray:
    """A laser at ``pose`` in an irregular 6 x 4 m room: its scan's points in its frame."""
    walls = [((-3, -2), (3, -2)), ((3, -2), (3, 2)), ((3, 2), (-3, 2)), ((-3, 2), (-3, -2)),
             ((0.5, -2), (1.5, -0.8)), ((-2, 1), (-1, 2))]
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    ranges = np.full(angles.size, np.inf)
    for (ax, ay), (bx, by) in walls:
        for i, a in enumerate(angles + pose.theta):
            d = np.array([math.cos(a), math.sin(a)])
            e = np.array([bx - ax, by - ay])
            m = np.array([[d[0], -e[0]], [d[1], -e[1]]])
            if abs(np.linalg.det(m)) < 1e-12:
                continue
            t, s = np.linalg.solve(m, np.array([ax - pose.x, ay - pose.y]))
            if t > 0 and 0 <= s <= 1:
                ranges[i] = min(ranges[i], t)
    ranges += rng.normal(0, 0.005, ranges.size)
    return scan_points(ranges, -math.pi, 2 * math.pi / 360, 12.0)


def test_icp_finds_a_scans_motion() -> None:
    rng = np.random.default_rng(2)
    a, b = Pose2(0.1, 0.2, 0.3), Pose2(0.35, 0.1, 0.7)
    truth = a.inverse() * b
    found, rms = match_scans(_room_points(a, rng), _room_points(b, rng),
                             Pose2(truth.x + 0.05, truth.y - 0.04, truth.theta + 0.05))
    assert found.distance(truth) < 0.01 and abs(found.theta - truth.theta) < 0.005
    assert rms < 0.02
    with pytest.raises(ValueError, match="ten points"):
        match_scans(np.zeros((3, 2)), np.zeros((30, 2)), Pose2())


def test_the_laser_mount_from_turns_and_a_straight_move() -> None:
    mount = Pose2(0.12, -0.03, 0.05)
    bases = [Pose2(0, 0, 0.3 * k) for k in range(22)] + [
        Pose2(0.12 * k, 0, 6.6) for k in range(1, 5)]
    pairs = [ScanPair(b1.inverse() * b2, mount.inverse() * (b1.inverse() * b2) * mount)
             for b1, b2 in itertools.pairwise(bases)]
    est = laser_mount(pairs)
    assert est.mount.distance(mount) < 1e-6 and abs(est.mount.theta - mount.theta) < 1e-6
    assert est.residual < 1e-6
    with pytest.raises(ValueError, match="straight move"):
        laser_mount(pairs[:20])


def _step(chassis: Any, seconds: float, dt: float = 0.02) -> None:
    for _ in range(round(seconds / dt)):
        chassis.step(dt)


def _run(chassis: Any, device: CalibrationDevice, name: str, timeout: float) -> Any:
    """Step the chassis until ``name``'s calibration stops measuring (sim seconds), then wait
    for its estimate (worked out on a thread for the laser)."""
    run = device.runs[name]
    for _ in range(round(timeout / 0.02)):
        chassis.step(0.02)
        if run.state != "CALIBRATING" or (name == "laser" and not run.phase):
            break
    else:
        raise AssertionError(f"{name} still calibrating after {timeout} s: {run}")
    assert wait_for(lambda: run.state != "CALIBRATING", 30), run
    return run


def test_the_imu_calibration_measures_the_bias_and_takes_it_off() -> None:
    cal, (chassis, node) = build_device(CalibrationDevice, {"imu_gyro_bias": 0.01, "seed": 3})
    imu = chassis.device(ImuDevice)
    serve = node.services["calibration/command"]
    _step(chassis, 0.1)
    assert imu.gyro == pytest.approx(0.01, abs=0.01)  # uncalibrated: the bias is in
    res = serve(CalibrateRequest(device="imu", command="start"))
    assert res.success and res.state.state == "CALIBRATING"
    assert not serve(CalibrateRequest(device="imu", command="start")).success
    assert cal.changed()
    cal.publish(node.stamp())  # the node's schedule publishes a changed device at once
    run = _run(chassis, cal, "imu", 5)
    cal.publish(node.stamp())
    assert run.state == "CALIBRATED" and run.values[0] == pytest.approx(0.01, abs=5e-4)
    assert run.accuracy > 90 and imu.bias_estimate == run.values[0]
    readings = []
    for _ in range(200):
        chassis.step(0.02)
        readings.append(imu.gyro)
    assert abs(float(np.mean(readings))) < 5e-4  # the bias is gone from the readings
    states = [m for m in node.publishers["calibration/state"].sent if m.device == "imu"]
    assert states[0].state == "CALIBRATING" and states[-1].state == "CALIBRATED"
    # moving spoils it; bad requests say why
    assert serve(CalibrateRequest(device="imu", command="start")).success
    chassis.sim.drive.command(0.3, 0.0, chassis.sim.time)
    assert _run(chassis, cal, "imu", 5).state == "FAILED"
    assert "moved" in cal.runs["imu"].message
    assert "stand still" in serve(CalibrateRequest(device="imu", command="start")).message
    assert "no calibration 'gps'" in serve(CalibrateRequest(device="gps")).message
    assert "unknown command 'go'" in serve(CalibrateRequest(device="imu", command="go")).message


def misalignment(chassis: Any, laser: LaserDevice) -> float:
    """How far apart two scans of one room lie (mean distance of each point of one to the
    wall through the nearest of the other, m) when put in the map with the published mount, taken a quarter
    turn apart where the robot stands: what a wrong mount does to SLAM and localisation."""
    here = chassis.sim.truth
    c = laser.laser.config
    clouds = []
    for turn in (0.0, math.pi / 2):
        chassis.sim.truth = Pose2(here.x, here.y, here.theta + turn)
        pts = scan_points(laser.ranges(), c.angle_min, c.angle_increment, c.range_max)
        at = chassis.sim.truth * laser.mount
        clouds.append(pts @ np.array([[math.cos(at.theta), math.sin(at.theta)],
                                      [-math.sin(at.theta), math.cos(at.theta)]]) + (at.x, at.y))
    chassis.sim.truth = here
    tree = cKDTree(clouds[0])
    dist, idx = tree.query(clouds[1])
    near = dist < 0.5
    off = np.einsum("ij,ij->i", normals(clouds[0], tree)[idx[near]],
                    clouds[1][near] - clouds[0][idx[near]])
    return float(np.mean(np.abs(off)))


def test_the_laser_calibration_finds_the_mount_error_and_applies_it() -> None:
    cal, (chassis, node) = build_device(CalibrationDevice, {
        "laser_error_x": 0.04, "laser_error_yaw": 0.06, "seed": 4, "range_noise": 0.01,
        "odom_noise": 0.02})
    laser = chassis.device(LaserDevice)
    serve = node.services["calibration/command"]
    assert "only a CALIBRATED" in serve(CalibrateRequest(device="laser",
                                                         command="complete")).message
    res = serve(CalibrateRequest(device="laser", command="start"))
    assert res.success, res.message
    assert chassis.sim.drive.held_by == "laser calibration"
    start = chassis.sim.truth
    run = _run(chassis, cal, "laser", 60)
    assert run.state == "CALIBRATED", run.message
    x, y, yaw = run.values
    true = laser.true_mount
    assert math.hypot(x - true.x, y - true.y) < 0.01 and abs(yaw - true.theta) < 0.005, (
        run.values, true)
    assert chassis.sim.drive.held_by is None and chassis.sim.truth.distance(start) < 0.1
    assert laser.mount != true  # not applied before complete
    before = misalignment(chassis, laser)
    assert serve(CalibrateRequest(device="laser", command="complete")).success
    after = misalignment(chassis, laser)
    print(f"scans a quarter turn apart: {1000 * before:.1f} mm apart before, "
          f"{1000 * after:.1f} mm after")
    assert after < before / 3  # the scans line up
    assert laser.mount == Pose2(x, y, yaw) and run.applied == [x, y, yaw]
    assert node.static[-1].child_frame_id == "laser"
    assert node.static[-1].transform.translation.x == pytest.approx(x)


def test_the_camera_calibration_finds_the_lens_and_yaw_from_a_board() -> None:
    cal, (chassis, node) = build_device(CalibrationDevice, {
        "camera_error_f": 0.08, "camera_error_yaw": 0.05, "seed": 5, "range_noise": 0.005})
    serve = node.services["calibration/command"]
    camera = chassis.device(CameraDevice)
    res = serve(CalibrateRequest(device="camera", command="start"))
    assert not res.success and "no calibration board in view" in res.message
    here = chassis.sim.truth
    ahead = here * Pose2(1.8, 0.1, 0.0)
    chassis.sim.world.set_obstacles([Obstacle("board", "box", ahead.x, ahead.y, here.theta,
                                              size_x=0.05, size_y=0.8)])
    res = serve(CalibrateRequest(device="camera", command="start"))
    assert res.success, res.message
    assert chassis.sim.drive.held_by == "camera calibration"
    run = _run(chassis, cal, "camera", 30)
    assert run.state == "CALIBRATED", run.message
    f, yaw = run.values
    nominal = camera.config.f
    assert f == pytest.approx(nominal * 1.08, rel=0.01) and yaw == pytest.approx(0.05, abs=0.003)
    assert len(run.sightings) >= 20 and run.accuracy > 70, run.message
    assert chassis.sim.drive.held_by is None
    assert abs(chassis.sim.truth.theta - here.theta) < 0.03  # turned back to face the board
    assert serve(CalibrateRequest(device="camera", command="complete")).success
    front = camera.view("front")
    assert front.k[0] == pytest.approx(f) and front.published.theta == pytest.approx(yaw)
    link = [t for t in node.static if t.child_frame_id == "camera_front_link"][-1]
    assert link.transform.rotation.z == pytest.approx(math.sin(yaw / 2))
