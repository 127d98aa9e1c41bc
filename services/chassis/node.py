"""`ChassisNode`: wires the simulated chassis (body and devices) to topics, TF and services."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any, TypeVar

from zenros.clock import Time
from zenros.message import Message, ServiceType
from zenros.msgs.geometry_msgs import TransformStamped, Twist
from zenros.msgs.rosgraph_msgs import Clock
from zenros.msgs.std_srvs import SetBool, SetBoolRequest, SetBoolResponse
from zenros.msgs.zenros_msgs import (
    SetObstacles,
    SetObstaclesRequest,
    SetObstaclesResponse,
    Teleport,
    TeleportRequest,
    TeleportResponse,
)
from zenros.node import Node
from zenros.qos import QOS_SENSOR, QoSProfile
from zenros.se2 import Pose2
from zenros.tf import StaticTransformBroadcaster, TransformBroadcaster

from .config import declare_chassis
from .device import Device, Schedule
from .diagnostics import chassis_diagnostics
from .drive import CommandError
from .obstacle_requests import apply_request, requested, to_msgs

__all__ = ["ChassisNode"]

_NS = 1_000_000_000
_NAP = 0.05  # s: the loop sleeps at most this long at once, so that a close never waits more

M = TypeVar("M", bound=Message)
D = TypeVar("D", bound=Device[Any])


class ChassisNode(Node):
    """The simulated chassis: a diff-drive base in a 2-D world, with its devices.

    The base: ``cmd_vel``, ``chassis/set_estop``, ``sim/teleport``, ``sim/set_obstacles``
    and ``/clock``. The devices (`devices.DEVICES`) publish the rest: ``odom`` and ``/tf``,
    ``sim/ground_truth``, ``battery_state``, ``scan`` and ``/tf_static``, ``chassis/io``
    and ``chassis/set_io``, ``chassis/state``, the shared world's bodies. This node is
    their `Endpoints`: what they open runs its callbacks under the simulation's lock.
    Parameters: `ChassisParameters`, each device's, and docs/chassis.md.
    """

    node_name = "chassis"

    def setup(self) -> None:
        cfg = declare_chassis(self.parameters)
        self.cfg = cfg
        self.chassis = cfg.build(self.logger)
        self.sim = self.chassis.sim
        self.pacer = self.chassis.pacer
        self.dt = 1.0 / cfg.rate
        self._dt_ns = round(self.dt * _NS)
        self._start_ns = time.time_ns()
        self._sim_lock = threading.RLock()
        self._steps = 0
        self._bad_cmds = 0
        self._tf: TransformBroadcaster | None = None
        self._static_tf: StaticTransformBroadcaster | None = None

        self.clock_pub = (self.create_publisher(Clock, "/clock", QOS_SENSOR)
                          if cfg.publish_clock else None)
        self.cmd_sub = self.create_subscription(Twist, "cmd_vel", self.on_cmd_vel)
        self.serve(Teleport, "sim/teleport", self.handle_teleport)
        self.serve(SetObstacles, "sim/set_obstacles", self.handle_set_obstacles)
        self.serve(SetBool, "chassis/set_estop", self.handle_set_estop)
        for device in self.chassis.devices:
            device.open(self)
        self.schedule = Schedule(self.chassis.devices, cfg.rate)
        self.diagnostics = chassis_diagnostics(self)  # motors, battery, laser on /diagnostics
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

    def device(self, kind: type[D]) -> D | None:
        """The chassis's device of type ``kind`` (`devices.DEVICES`), or None."""
        return self.chassis.device(kind)

    # ------------------------------------------------------------------ time

    def stamp(self) -> Time:
        """The current sim time (from the wall clock at start when /clock is published)."""
        if self.cfg.publish_clock:
            return Time.from_nanoseconds(self._start_ns + self._steps * self._dt_ns)
        return Time.from_nanoseconds(time.time_ns())

    # ------------------------------------------------------------------ what devices open

    def listen(self, msg_type: type[M], topic: str, callback: Callable[[M], object],
               qos: QoSProfile | int = 10) -> None:
        """Subscribe ``callback`` to ``topic``; it runs under the simulation's lock."""
        def locked(msg: M) -> None:
            with self._sim_lock:
                callback(msg)

        self.create_subscription(msg_type, topic, locked, qos)

    def serve(self, srv_type: ServiceType, name: str,
              handler: Callable[[Any], Message]) -> None:
        """Serve ``name`` with ``handler``; it runs under the simulation's lock."""
        def locked(req: Any) -> Message:
            with self._sim_lock:
                return handler(req)

        self.create_service(srv_type, name, locked)

    def transforms(self) -> TransformBroadcaster:
        """The node's one ``/tf`` broadcaster."""
        if self._tf is None:
            self._tf = TransformBroadcaster(self)
        return self._tf

    def static_transform(self, transform: TransformStamped) -> None:
        """Add a link to the node's ``/tf_static``."""
        if self._static_tf is None:
            self._static_tf = StaticTransformBroadcaster(self)
        self._static_tf.send_transform(transform)

    # ------------------------------------------------------------------ the base's inputs

    def on_cmd_vel(self, msg: Twist) -> None:
        with self._sim_lock:
            if self.sim.drive.held_by is not None:  # a calibration drives (calibration/state)
                return
            try:
                self.sim.drive.command(msg.linear.x, msg.angular.z, self.sim.time)
            except CommandError as exc:
                self.logger.warning("cmd_vel refused, stopping: %s", exc)

    def handle_teleport(self, req: TeleportRequest) -> TeleportResponse:
        why = self.sim.teleport(Pose2(req.pose.x, req.pose.y, req.pose.theta))
        if why:
            return TeleportResponse(success=False, message=why)
        self.logger.info("teleported to (%.2f, %.2f, %.2f)", req.pose.x, req.pose.y,
                         req.pose.theta)
        return TeleportResponse(success=True, message="")

    def handle_set_obstacles(self, req: SetObstaclesRequest) -> SetObstaclesResponse:
        why = apply_request(self.sim, req)
        now = to_msgs(requested(self.sim.world.obstacles.values()))
        return SetObstaclesResponse(success=not why, message=why, obstacles=now)

    def handle_set_estop(self, req: SetBoolRequest) -> SetBoolResponse:
        self.sim.drive.set_estop(bool(req.data))
        self.logger.warning("e-stop %s", "ENGAGED" if req.data else "released")
        return SetBoolResponse(success=True,
                               message="e-stop engaged" if req.data else "e-stop released")

    # ------------------------------------------------------------------ the loop

    def _loop(self) -> None:
        try:
            while not self._stop.is_set():
                delay = self.pacer.delay()
                if delay > 0:  # a plain sleep wakes for less CPU than an Event's wait
                    time.sleep(min(delay, _NAP))
                    if delay > _NAP or self._stop.is_set():
                        continue
                with self._sim_lock:
                    self._check_bad_cmds()
                    self.chassis.step(self.dt)
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
        stamp = self.stamp()
        if self.clock_pub is not None and self.clock_pub.subscription_count:
            self.clock_pub.publish(Clock(clock=stamp))
        self.schedule.publish(self._steps, stamp)

    def _stop_loop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5)
