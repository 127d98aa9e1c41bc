"""The robot's calibrations (docs/chassis.md, Calibration): ``calibration/command``
(zenros_msgs/Calibrate) and ``calibration/state`` (zenros_msgs/CalibrationState, latched: a
late joiner gets the latest change).

- **imu**: the robot must stand still; the gyro is read every physics step for
  ``imu_calibration_time`` sim seconds and its mean is the bias, taken off every reading from
  then on (applied at once: an IMU calibration has no ``complete``). Moving during it fails.
- **laser**: the robot drives itself (``cmd_vel`` is dropped meanwhile): one turn in place,
  then ``laser_calibration_drive`` metres straight ahead and back, keeping a scan and the
  odometry every 0.3 rad or 0.12 m. The scans are matched pairwise (ICP) and the mount that
  best explains laser motion against base motion is the result (`calibration.laser_mount`),
  ``CALIBRATED`` until ``complete`` publishes it on ``/tf_static`` (or ``cancel`` drops it).
  It needs 1 m free ahead and behind, and stops on a contact, an e-stop or the dock.
- **camera** (the front one): the robot must face a board (an obstacle 0.2-1.5 m wide,
  standing out of what is behind it) 0.5-4 m ahead. It turns 0.25 rad left, 0.5 right and
  back, seeing the board's edges with the laser (range steps) and in the camera's middle
  row (its colour) every 0.04 rad; the focal length and yaw that map the one onto the
  other are the result (`calibration.camera_lens`), ``complete`` puts them in the camera's
  CameraInfo and on ``/tf_static``.

The robot drives itself in the laser's and the camera's (``cmd_vel`` is dropped meanwhile),
and stops on a contact, the e-stop or the dock.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field
from typing import Annotated

import msgspec
import numpy as np
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import Calibrate, CalibrateRequest, CalibrateResponse, CalibrationState
from zenros.pubsub import Publisher
from zenros.qos import QOS_LATCHED
from zenros.se2 import Pose2

from ..calibration import (
    ScanPair,
    board_edges,
    camera_lens,
    gyro_bias,
    image_edges,
    laser_mount,
    match_scans,
    scan_points,
)
from ..camera import OBSTACLE_RGB
from ..device import Chassis, Device, Endpoints
from ..param_types import Positive
from .camera import CameraDevice
from .dock import DockDevice
from .imu import ImuDevice
from .laser import LaserDevice
from .odometry import OdometryDevice

__all__ = ["CalibrationDevice", "CalibrationParameters"]

TURN_SPEED, DRIVE_SPEED = 0.5, 0.15  # rad/s, m/s of the laser calibration's moves
KEY_TURN, KEY_MOVE = 0.3, 0.12  # a scan is kept every this much turn (rad) or travel (m)
CLEARANCE = 1.0  # m free ahead and behind for the laser calibration's straight moves
SWEEP, SWEEP_SPEED, SIGHTING = 0.25, 0.2, 0.04  # rad, rad/s, rad: the camera's turns
BOARD_RANGE = (0.5, 4.0)  # m: where a camera calibration's board may stand
STILL = 1e-3  # m/s and rad/s below which the base stands still


@dataclass(frozen=True)
class _Move:
    """One leg of a calibration's drive: ``linear``, ``angular`` until ``amount`` (rad of
    turn, or m of travel) is done."""

    name: str
    linear: float
    angular: float
    amount: float


class CalibrationParameters(msgspec.Struct, kw_only=True, frozen=True):
    calibration: Annotated[bool, Meta(description="offer the IMU and laser calibrations")] = True
    imu_calibration_time: Annotated[Positive, Meta(
        le=60, description="sim seconds the gyro is averaged while the robot stands still")] = 2.0
    laser_calibration_drive: Annotated[Positive, Meta(
        le=0.8, description="metres the laser calibration drives ahead and back")] = 0.5


@dataclass
class _Run:
    """One calibration's state (the message's fields) and its measurements."""

    device: str
    names: list[str]
    applied: list[float]
    state: str = "FREE"
    progress: float = 0.0
    accuracy: float = 0.0
    message: str = ""
    values: list[float] = field(default_factory=list)
    samples: list[float] = field(default_factory=list)  # the imu's gyro readings
    keys: list[tuple[Pose2, np.ndarray, str]] = field(default_factory=list)  # odom, scan, phase
    sightings: list[tuple[float, float]] = field(default_factory=list)  # camera: bearing, u
    moves: list[_Move] = field(default_factory=list)  # the drive still to do (first: now)
    done: float = 0.0  # of the current move
    whole: float = 0.0  # of all the drive
    since: float = 0.0  # turn or travel since the last scan or sighting
    t: float = 0.0

    @property
    def phase(self) -> str:
        return self.moves[0].name if self.moves else ""

    def msg(self, stamp: Time, frame: str) -> CalibrationState:
        return CalibrationState(
            header=Header(stamp=stamp, frame_id=frame), device=self.device, state=self.state,
            progress=round(self.progress, 3), accuracy=round(self.accuracy, 1),
            message=self.message, names=list(self.names), values=list(self.values),
            applied=list(self.applied))

    def begin(self) -> None:
        self.state, self.progress, self.accuracy, self.message = "CALIBRATING", 0.0, 0.0, ""
        self.values, self.samples, self.keys, self.sightings = [], [], [], []
        self.moves, self.done, self.whole, self.since, self.t = [], 0.0, 0.0, 0.0, 0.0

    def fail(self, why: str) -> None:
        self.state, self.message, self.progress = "FAILED", why, 0.0


class CalibrationDevice(Device[CalibrationParameters]):
    """The IMU's, the laser's and the front camera's calibrations, run in the physics
    steps."""

    Parameters = CalibrationParameters
    rate = 2.0  # state messages a sim second while one runs
    _node: Endpoints
    _pub: Publisher[CalibrationState]

    def __init__(self, params: CalibrationParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.imu = chassis.device(ImuDevice)
        self.laser = chassis.device(LaserDevice)
        self.odometry = chassis.device(OdometryDevice)
        self.dock = chassis.device(DockDevice)
        self.camera = chassis.device(CameraDevice)
        self.runs: dict[str, _Run] = {}
        if self.imu is not None and self.imu.rate > 0:
            self.runs["imu"] = _Run("imu", ["gyro_bias_z"], [self.imu.bias_estimate])
        if self.laser is not None and self.odometry is not None:
            m = self.laser.mount
            self.runs["laser"] = _Run("laser", ["x", "y", "yaw"], [m.x, m.y, m.theta])
            if self.camera is not None and self.camera.rate > 0:
                self.runs["camera"] = _Run("camera", ["f", "yaw"], [self.camera.config.f, 0.0])
        self._dirty: set[str] = set()
        self._lock = threading.Lock()  # the laser's estimate is worked out off the sim lock
        self.inert = not params.calibration or not self.runs

    def open(self, node: Endpoints) -> None:
        if not self.params.calibration or not self.runs:
            self.runs = {}
            return
        self._node = node
        self._pub = node.create_publisher(CalibrationState, "calibration/state", QOS_LATCHED)
        node.serve(Calibrate, "calibration/command", self.on_command)

    # ------------------------------------------------------------------ commands

    def on_command(self, req: CalibrateRequest) -> CalibrateResponse:
        with self._lock:
            run = self.runs.get(req.device)
            if run is None:
                return CalibrateResponse(message=f"no calibration {req.device!r}: this robot "
                                                 f"calibrates {', '.join(sorted(self.runs))}")
            why = self._command(run, req.command)
            self._dirty.add(run.device)
            return CalibrateResponse(success=not why, message=why,
                                     state=run.msg(self._node.stamp(), self._frame))

    def _command(self, run: _Run, command: str) -> str:
        """Carry out ``command`` on ``run``; why not, or ""."""
        if command == "status":
            return ""
        if command == "start":
            return self._start(run)
        if command == "cancel":
            if run.state == "FREE":
                return f"no {run.device} calibration to cancel"
            self._release(run)
            run.moves = []
            run.state, run.progress, run.message = "FREE", 0.0, "cancelled"
            return ""
        if command == "complete":
            if run.state != "CALIBRATED":
                return (f"the {run.device} calibration is {run.state}: only a CALIBRATED one "
                        "can be completed")
            if run.device == "laser" and self.laser is not None:
                x, y, yaw = run.values
                self.laser.set_mount(Pose2(x, y, yaw))
            elif run.device == "camera" and self.camera is not None:
                f, yaw = run.values
                self.camera.set_calibration("front", f, self.camera.config.width / 2, yaw)
            run.applied = list(run.values)
            run.state, run.message = "FREE", "applied"
            return ""
        return f"unknown command {command!r}: start, cancel, complete or status"

    def _start(self, run: _Run) -> str:
        if run.state == "CALIBRATING":
            return f"the {run.device} calibration is running already"
        why = self._cannot_start(run.device)
        if why:
            return why
        run.begin()
        if run.device == "laser":
            d = self.params.laser_calibration_drive
            run.moves = [_Move("turn", 0.0, TURN_SPEED, 2 * math.pi),
                         _Move("ahead", DRIVE_SPEED, 0.0, d), _Move("back", -DRIVE_SPEED, 0.0, d)]
            self._add_key(run)
        elif run.device == "camera":
            run.moves = [_Move("left", 0.0, SWEEP_SPEED, SWEEP),
                         _Move("right", 0.0, -SWEEP_SPEED, 2 * SWEEP),
                         _Move("centre", 0.0, SWEEP_SPEED, SWEEP)]
            self._sight(run)
        if run.moves:
            run.whole = sum(m.amount for m in run.moves)
            self.chassis.sim.drive.hold(f"{run.device} calibration")
        return ""

    def _cannot_start(self, device: str) -> str:
        sim = self.chassis.sim
        if abs(sim.linear) > STILL or abs(sim.angular) > STILL:
            return f"the robot must stand still to start the {device} calibration"
        if sim.drive.estop:
            return "the e-stop is engaged"
        if device == "imu":
            return ""
        if any(r.state == "CALIBRATING" for r in self.runs.values()):
            return "another calibration is running"
        if self.dock is not None and self.dock.docked:
            return "the robot is on its dock: undock it first"
        if device == "laser":
            assert self.laser is not None
            ranges = self.laser.ranges()
            c = self.laser.laser.config
            angles = c.angle_min + c.angle_increment * np.arange(ranges.size)
            heading = np.abs(np.sin(angles + self.laser.true_mount.theta)) < 0.35
            if np.any(np.isfinite(ranges[heading]) & (ranges[heading] < CLEARANCE)):
                return (f"the laser calibration drives {self.params.laser_calibration_drive:g}"
                        f" m ahead and back: it needs {CLEARANCE:g} m free both ways")
        if device == "camera" and self._sighting() is None:
            return (f"no calibration board in view: face the robot to a board (0.2-1.5 m wide, "
                    f"standing out of what is behind it) {BOARD_RANGE[0]:g}-{BOARD_RANGE[1]:g} "
                    "m ahead, whole in the front camera's view")
        return ""

    def _release(self, run: _Run) -> None:
        drive = self.chassis.sim.drive
        if drive.held_by == f"{run.device} calibration":
            drive.hold(None)

    # ------------------------------------------------------------------ steps

    def step(self, dt: float) -> None:
        with self._lock:
            for run in self.runs.values():
                if run.state != "CALIBRATING":
                    continue
                before = run.progress
                if run.device == "imu":
                    self._step_imu(run, dt)
                elif run.moves:
                    self._step_drive(run, dt)
                if run.state != "CALIBRATING" or int(run.progress * 10) != int(before * 10):
                    self._dirty.add(run.device)

    def _step_imu(self, run: _Run, dt: float) -> None:
        assert self.imu is not None
        sim = self.chassis.sim
        if abs(sim.linear) > STILL or abs(sim.angular) > STILL:
            run.fail("the robot moved during the IMU calibration")
            return
        run.samples.append(self.imu.gyro_raw)
        run.t += dt
        run.progress = min(1.0, run.t / self.params.imu_calibration_time)
        if run.progress < 1.0:
            return
        bias, err = gyro_bias(run.samples)
        self.imu.bias_estimate = bias
        run.values = run.applied = [bias]
        run.accuracy = 100.0 * max(0.0, 1.0 - err / 0.01)
        run.state, run.message = "CALIBRATED", (
            f"gyro bias {bias:.5f} rad/s (± {err:.5f}) from {len(run.samples)} readings, "
            "applied")

    def _step_drive(self, run: _Run, dt: float) -> None:
        """One step of a calibration's drive: stop it on trouble, keep what its device keeps,
        go on to the next move, and at the end work the result out."""
        sim, drive = self.chassis.sim, self.chassis.sim.drive
        docked = self.dock is not None and self.dock.docked
        if drive.held_by != f"{run.device} calibration" or drive.estop or sim.bumper or docked:
            self._release(run)
            run.moves = []
            run.fail(f"the {run.device} calibration stopped: " + (
                "e-stop" if drive.estop else "contact" if sim.bumper else "on the dock"
                if docked else "the base was taken"))
            return
        gone = abs(sim.angular) * dt if run.moves[0].angular else abs(sim.linear) * dt
        run.done += gone
        run.since += gone
        if run.device == "laser":
            assert self.odometry is not None
            rel = run.keys[-1][0].inverse() * self.odometry.odometry.pose
            if abs(rel.theta) >= KEY_TURN or math.hypot(rel.x, rel.y) >= KEY_MOVE:
                self._add_key(run)
        elif run.since >= SIGHTING:
            self._sight(run)
        if run.done >= run.moves[0].amount:
            run.moves.pop(0)
            run.done = 0.0
            if run.device == "laser":
                self._add_key(run)  # the ends of the moves are kept too
        left = sum(m.amount for m in run.moves) - run.done
        run.progress = min(0.9, 0.9 * (1.0 - left / run.whole))
        if run.moves:
            m = run.moves[0]
            drive.command(m.linear, m.angular, sim.time)
            return
        self._release(run)
        run.progress = 0.95
        if run.device == "laser":
            threading.Thread(target=self._estimate_laser, args=(run, list(run.keys)),
                             name="laser-calibration", daemon=True).start()
        else:
            self._estimate_camera(run)

    def _add_key(self, run: _Run) -> None:
        assert self.laser is not None and self.odometry is not None
        c = self.laser.laser.config
        run.keys.append((self.odometry.odometry.pose,
                         scan_points(self.laser.ranges(), c.angle_min, c.angle_increment,
                                     c.range_max), run.phase))
        run.since = 0.0

    def _sighting(self) -> list[tuple[float, float]] | None:
        """The board's two edges now: (bearing from the front camera in the base frame, the
        column where the camera sees it), or None when the laser or the camera misses it."""
        assert self.laser is not None and self.camera is not None
        view = self.camera.view("front")
        if view is None:
            return None
        c, lm = self.laser.laser.config, self.laser.mount
        half = 0.85 * self.camera.config.hfov / 2
        window = (view.published.theta - half - lm.theta, view.published.theta + half - lm.theta)
        edges = board_edges(self.laser.ranges(), c.angle_min, c.angle_increment, window)
        frame = self.camera.frame_now("front")
        seen = image_edges(frame[frame.shape[0] // 2], OBSTACLE_RGB)
        if edges is None or seen is None or seen[0] <= 0 or seen[1] >= frame.shape[1]:
            return None
        bearings = []
        for a, r in edges:
            if not BOARD_RANGE[0] <= r <= BOARD_RANGE[1]:
                return None
            px, py = lm.apply(r * math.cos(a), r * math.sin(a))
            bearings.append(math.atan2(py - view.published.y, px - view.published.x))
        # the lower bearing (the board's right edge) is the higher column
        return [(bearings[0], seen[1]), (bearings[1], seen[0])]

    def _sight(self, run: _Run) -> None:
        got = self._sighting()
        if got is not None:
            run.sightings.extend(got)
        run.since = 0.0

    def _estimate_camera(self, run: _Run) -> None:
        assert self.camera is not None
        try:
            est = camera_lens(run.sightings, self.camera.config.width / 2)
        except Exception as exc:  # a fault here must end the run, never the physics step
            if not isinstance(exc, ValueError):
                self.chassis.logger.exception("camera calibration: the estimate failed")
            run.fail(f"the camera calibration could not solve: {exc}")
            return
        run.values = [est.f, est.yaw]
        assert self.laser is not None  # the laser's beam spacing, in pixels, scales the residual
        beam = est.f * self.laser.laser.config.angle_increment
        run.accuracy = 100.0 * max(0.0, 1.0 - est.residual / (2 * beam))
        run.progress = 1.0
        run.state, run.message = "CALIBRATED", (
            f"front camera: focal length {est.f:.1f} px, yaw {math.degrees(est.yaw):.2f} deg "
            f"from {len(run.sightings)} sightings of the board (residual {est.residual:.2f} "
            "px); complete to apply")

    def _estimate_laser(self, run: _Run, keys: list[tuple[Pose2, np.ndarray, str]]) -> None:
        """Off the sim lock: match the kept scans pairwise (each with the next; along the
        straight moves also every scan with every later one: the longer the baseline, the
        better it fixes the yaw) and solve for the mount."""
        assert self.laser is not None
        guess = self.laser.mount
        straight = [i for i, k in enumerate(keys) if k[2] in ("ahead", "back")]
        which = {(i, i + 1) for i in range(len(keys) - 1)} | {
            (i, j) for i in straight for j in straight if j > i}
        pairs: list[ScanPair] = []
        residuals: list[float] = []
        try:
            for i, j in sorted(which):
                (o1, s1, _), (o2, s2, _) = keys[i], keys[j]
                base = o1.inverse() * o2
                seen, rms = match_scans(s1, s2, guess.inverse() * base * guess)
                pairs.append(ScanPair(base, seen))
                residuals.append(rms)
            est = laser_mount(pairs)
        except Exception as exc:  # a fault here must end the run, not leave it CALIBRATING
            if not isinstance(exc, ValueError):
                self.chassis.logger.exception("laser calibration: the estimate failed")
            with self._lock:
                run.fail(f"the laser calibration could not solve: {exc}")
                self._dirty.add(run.device)
            return
        with self._lock:
            if run.state != "CALIBRATING":  # cancelled meanwhile
                return
            m = est.mount
            run.values = [m.x, m.y, m.theta]
            run.accuracy = 100.0 * max(0.0, 1.0 - est.residual / 0.05)
            run.progress = 1.0
            run.state, run.message = "CALIBRATED", (
                f"laser at ({m.x:.3f}, {m.y:.3f}) m, yaw {math.degrees(m.theta):.2f} deg on the "
                f"base from {len(pairs)} scan pairs (residual {est.residual * 1000:.1f} mm, "
                f"scan match {1000 * float(np.median(residuals)):.1f} mm); complete to apply")
            self._dirty.add(run.device)

    # ------------------------------------------------------------------ state

    @property
    def _frame(self) -> str:
        return self.chassis.frames.base

    def changed(self) -> bool:
        return bool(self._dirty)

    def publish(self, stamp: Time) -> None:
        if not self.runs:
            return
        with self._lock:
            due = self._dirty | {d for d, r in self.runs.items() if r.state == "CALIBRATING"}
            self._dirty = set()
            msgs = [self.runs[d].msg(stamp, self._frame) for d in sorted(due)]
        for m in msgs:
            self._pub.publish(m)
