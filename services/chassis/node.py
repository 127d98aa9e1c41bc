"""`ChassisNode`: wires the simulated base (`Simulation`) to topics, TF and services."""

from __future__ import annotations

import threading
import time

from zenros.clock import Time
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.rosgraph_msgs import Clock
from zenros.msgs.sensor_msgs import BatteryState, LaserScan
from zenros.msgs.std_msgs import Header
from zenros.msgs.std_srvs import SetBool, SetBoolRequest, SetBoolResponse
from zenros.msgs.zenros_msgs import (
    ChassisState,
    IoState,
    SetIo,
    SetIoRequest,
    SetIoResponse,
    SetObstacles,
    SetObstaclesRequest,
    SetObstaclesResponse,
    Teleport,
    TeleportRequest,
    TeleportResponse,
)
from zenros.msgs.zenros_msgs import Obstacle as ObstacleMsg
from zenros.node import Node
from zenros.qos import QOS_LATCHED, QOS_SENSOR
from zenros.se2 import Pose2
from zenros.tf import StaticTransformBroadcaster, TransformBroadcaster

from . import messages
from .config import ChassisParameters, chassis_config
from .drive import CommandError
from .ioports import IoError, IoPorts
from .obstacle_requests import apply_request, to_msgs
from .pacer import Pacer
from .shared_world import BODY_PREFIX, SharedWorld

__all__ = ["ChassisNode"]

_NS = 1_000_000_000


class ChassisNode(Node):
    """The simulated chassis: a diff-drive base with a laser, battery and dock in a 2-D world.

    Publishes ``odom``, ``/tf`` (odom -> base_link), ``/tf_static`` (base_link -> laser),
    ``scan``, ``battery_state``, ``chassis/state``, ``sim/ground_truth`` and ``/clock``;
    takes ``cmd_vel``; serves ``sim/teleport``, ``sim/set_obstacles`` and
    ``chassis/set_estop``; IO ports on ``chassis/io`` (latched) and ``chassis/set_io``
    (`IoPorts`). Parameters: `ChassisParameters` and docs/chassis.md.
    """

    node_name = "chassis"

    def setup(self) -> None:
        params = self.declare_parameters(ChassisParameters, read_only=True)
        cfg = chassis_config(params)
        self.cfg = cfg
        self.sim = cfg.build(self.logger)
        self.dt = 1.0 / cfg.rate
        self.pacer = Pacer(self.dt, cfg.speed)
        self._dt_ns = round(self.dt * _NS)
        self._start_ns = time.time_ns()
        self._sim_lock = threading.RLock()
        self._steps = 0
        self._state_sent: tuple[bool, ...] | None = None
        self._bad_cmds = 0

        self.odom_pub = self.create_publisher(Odometry, "odom")
        self.truth_pub = self.create_publisher(Odometry, "sim/ground_truth")
        self.scan_pub = self.create_publisher(LaserScan, "scan", QOS_SENSOR)
        self.battery_pub = self.create_publisher(BatteryState, "battery_state")
        self.state_pub = self.create_publisher(ChassisState, "chassis/state")
        self.clock_pub = (self.create_publisher(Clock, "/clock", QOS_SENSOR)
                          if cfg.publish_clock else None)
        self.tf = TransformBroadcaster(self) if cfg.publish_tf else None
        self.cmd_sub = self.create_subscription(Twist, "cmd_vel", self.on_cmd_vel)
        self.create_service(Teleport, "sim/teleport", self.handle_teleport)
        self.create_service(SetObstacles, "sim/set_obstacles", self.handle_set_obstacles)
        self.create_service(SetBool, "chassis/set_estop", self.handle_set_estop)
        self.io = IoPorts(bool(self.declare_parameter("io_extension_board", True)))
        self.io_pub = self.create_publisher(IoState, "chassis/io", QOS_LATCHED)
        self.create_service(SetIo, "chassis/set_io", self.handle_set_io)
        self.io_pub.publish(self._io_state())
        self._pose_cov = messages.covariance(self.sim.odometry.pose_covariance())
        self._twist_cov = messages.covariance(self.sim.odometry.twist_covariance())
        self.shared: SharedWorld | None = None
        if params.world_topic:
            self.shared = SharedWorld(self.sim.world, self.namespace, cfg.robot_radius)
            self._world_every = max(1, round(cfg.rate / params.world_rate))
            self.body_pub = self.create_publisher(ObstacleMsg, params.world_topic)
            self.create_subscription(ObstacleMsg, params.world_topic, self.on_body)
        self.static_tf = StaticTransformBroadcaster(self)
        self.static_tf.send_transform(messages.transform(
            self.stamp(), cfg.base_frame, cfg.laser_frame, cfg.laser_mount, cfg.laser_z))
        t = self.sim.truth
        self.logger.info("world %s (%dx%d cells at %g m), robot at (%.2f, %.2f, %.2f), "
                         "speed %s, /clock %s", cfg.map_path, self.sim.world.width,
                         self.sim.world.height, self.sim.world.res, t.x, t.y, t.theta,
                         "max" if cfg.speed <= 0 else f"{cfg.speed:g}x",
                         "on" if cfg.publish_clock else "off")
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, name="chassis-sim", daemon=True)
        self._thread.start()
        self.on_close(self._stop_loop)

    # ------------------------------------------------------------------ time

    def stamp(self) -> Time:
        """The current sim time (from the wall clock at start when /clock is published)."""
        if self.cfg.publish_clock:
            return Time.from_nanoseconds(self._start_ns + self._steps * self._dt_ns)
        return Time.from_nanoseconds(time.time_ns())

    # ------------------------------------------------------------------ inputs

    def on_cmd_vel(self, msg: Twist) -> None:
        with self._sim_lock:
            try:
                self.sim.drive.command(msg.linear.x, msg.angular.z, self.sim.time)
            except CommandError as exc:
                self.logger.warning("cmd_vel refused, stopping: %s", exc)

    def on_body(self, msg: ObstacleMsg) -> None:
        """Another robot's body in the shared world (`SharedWorld`)."""
        assert self.shared is not None
        with self._sim_lock:
            self.shared.on_body(msg)

    def handle_teleport(self, req: TeleportRequest) -> TeleportResponse:
        with self._sim_lock:
            why = self.sim.teleport(Pose2(req.pose.x, req.pose.y, req.pose.theta))
        if why:
            return TeleportResponse(success=False, message=why)
        self.logger.info("teleported to (%.2f, %.2f, %.2f)", req.pose.x, req.pose.y,
                         req.pose.theta)
        return TeleportResponse(success=True, message="")

    def handle_set_obstacles(self, req: SetObstaclesRequest) -> SetObstaclesResponse:
        with self._sim_lock:
            why = apply_request(self.sim, req)
            now = to_msgs(o for o in self.sim.world.obstacles.values()
                          if not o.id.startswith(BODY_PREFIX))
        return SetObstaclesResponse(success=not why, message=why, obstacles=now)

    def handle_set_estop(self, req: SetBoolRequest) -> SetBoolResponse:
        with self._sim_lock:
            self.sim.drive.set_estop(bool(req.data))
        self.logger.warning("e-stop %s", "ENGAGED" if req.data else "released")
        return SetBoolResponse(success=True,
                               message="e-stop engaged" if req.data else "e-stop released")

    def _io_state(self) -> IoState:
        main, ext_out, ext_in = self.io.snapshot()
        return IoState(header=Header(stamp=self.stamp(), frame_id=self.cfg.base_frame),
                       outputs=main, ext_outputs=ext_out, ext_inputs=ext_in)

    def handle_set_io(self, req: SetIoRequest) -> SetIoResponse:
        try:
            changed = self.io.set(req.board, req.port, req.level)
        except IoError as exc:
            return SetIoResponse(success=False, message=str(exc), state=self._io_state())
        state = self._io_state()
        if changed:
            self.io_pub.publish(state)
            self.logger.info("IO %s port %d set %s", req.board, req.port,
                             "high" if req.level else "low")
        return SetIoResponse(success=True, message="", state=state)

    # ------------------------------------------------------------------ the loop

    def _loop(self) -> None:
        try:
            while not self._stop.is_set():
                delay = self.pacer.delay()
                if delay > 0 and self._stop.wait(delay):
                    break
                with self._sim_lock:
                    self._check_bad_cmds()
                    self.sim.step(self.dt)
                    self._steps += 1
                    self._publish()
                self.pacer.stepped()
        except Exception:  # the sim thread must say why it died
            if not self._stop.is_set():
                self.logger.exception("simulation loop failed; the chassis has stopped")

    def _check_bad_cmds(self) -> None:
        errors = self.cmd_sub.errors
        if errors != self._bad_cmds:
            self._bad_cmds = errors
            self.sim.drive.halt()
            self.logger.warning("cmd_vel: refused a message that is not a geometry_msgs/Twist;"
                                " stopping")

    def _publish(self) -> None:
        # a message nobody subscribes to is not built (publish would drop it unencoded);
        # latched publishers always count a subscriber, so their cache stays filled
        cfg, sim, k = self.cfg, self.sim, self._steps
        stamp = self.stamp()
        if self.clock_pub is not None and self.clock_pub.subscription_count:
            self.clock_pub.publish(Clock(clock=stamp))
        if k % cfg.odom_every == 0:
            odom = sim.odometry
            self.odom_pub.publish(messages.odometry(
                stamp, cfg.odom_frame, cfg.base_frame, odom.pose, odom.linear, odom.angular,
                self._pose_cov, self._twist_cov))
            if self.tf is not None:
                self.tf.send_transform(messages.transform(
                    stamp, cfg.odom_frame, cfg.base_frame, odom.pose))
            if self.truth_pub.subscription_count:
                self.truth_pub.publish(messages.odometry(
                    stamp, cfg.map_frame, cfg.base_frame, sim.truth, sim.drive.linear,
                    sim.drive.angular))
        if k % cfg.scan_every == 0 and self.scan_pub.subscription_count:
            self.scan_pub.publish(messages.laser_scan(
                stamp, cfg.laser_frame, sim.laser.config, sim.scan(), 1.0 / cfg.scan_rate))
        flags = self._flags()
        if k % cfg.state_every == 0 or flags != self._state_sent:
            self._state_sent = flags
            estop, bumper, docked, charging, timeout = flags
            self.state_pub.publish(ChassisState(
                header=Header(stamp=stamp, frame_id=cfg.base_frame), estop=estop,
                bumper=bumper, docked=docked, charging=charging, cmd_timeout=timeout,
                speed=cfg.speed, real_time_factor=self.pacer.factor,
                battery_percentage=sim.battery.percentage))
        if self.shared is not None and k % self._world_every == 0:
            body = self.shared.body(sim.truth)
            if self.shared.due(body):
                self.body_pub.publish(body)
            self.shared.prune()
        if k % cfg.battery_every == 0:
            self.battery_pub.publish(messages.battery_state(
                stamp, cfg.base_frame, sim.battery, sim.docked))

    def _flags(self) -> tuple[bool, bool, bool, bool, bool]:
        s = self.sim
        return (s.drive.estop, s.bumper, s.docked, s.battery.charging,
                s.drive.timed_out(s.time))

    def _stop_loop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5)

