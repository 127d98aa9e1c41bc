"""`RobotTopics`: the robot's topics into `Core`, the gateway's commands and status out.

Subscribes ``odom`` (polled at each status tick), ``battery_state``, ``chassis/state``,
``robot_pose`` and ``cmd_vel`` (relative to the node's namespace), not the laser's ``scan``
(10 Hz a robot the robot would send for nothing: the self test listens for one when asked); publishes ``galileo/status`` at ``rate`` Hz of wall
time (also under ``use_sim_time``), the dead-man speed command on ``cmd_vel`` and native
commands on ``galileo/cmds``.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable
from typing import Any

from zenros.clock import SteadyClock
from zenros.errors import UnknownTypeError
from zenros.msgs.diagnostic_msgs import DiagnosticArray, DiagnosticStatus
from zenros.msgs.galileo_msgs import GalileoHeader, GalileoNativeCmds, GalileoStatus
from zenros.msgs.geometry_msgs import PoseWithCovarianceStamped, Twist, Vector3
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.rcl_interfaces import Log
from zenros.msgs.sensor_msgs import BatteryState
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.qos import QOS_LATCHED, QoSProfile, Reliability
from zenros.registry import lookup_type
from zenros.tf.convert import yaw_from_msg

from ..state.core import Core

__all__ = ["RobotTopics"]

POLL_DEPTH = 256  # samples kept between two status ticks: 50 Hz odometry for 5 s
DEADMAN_PERIOD = 0.05  # s between dead-man commands on cmd_vel while driven
CONTROL_STALE = 0.5  # s without cmd_vel before the commanded speed reads 0
POWER_SUPPLY_STATUS_CHARGING = 1
POWER_SUPPLY_STATUS_FULL = 4


class RobotTopics:
    """Feeds ``core.state`` from the robot's topics and publishes the gateway's topics."""

    def __init__(self, node: Node, core: Core, rate: float = 30.0) -> None:
        self.node = node
        self.core = core
        self._control_at = 0.0
        # State first, endpoints after: their callbacks read it (and a node built outside
        # setup() has no delivery gate to hold them).
        self.seen: dict[str, float] = {}      # topic -> time.monotonic() of its last message
        self.log: deque[str] = deque(maxlen=500)
        self.on_native: Callable[[bytes], Any] | None = None
        self.status_pub = node.create_publisher(GalileoStatus, "galileo/status", 10)
        self.cmd_vel_pub = node.create_publisher(Twist, "cmd_vel", 10)
        self.cmds_pub = node.create_publisher(GalileoNativeCmds, "galileo/cmds", 10)
        # Odometry (50 Hz a robot) waits in Zenoh until the status tick takes it (`poll`): no
        # thread woken, nothing decoded but the newest (a fleet gateway at rest spent most of
        # its CPU on them). A polled subscription is best effort in effect (a ring of the
        # newest samples): it says so.
        polled = QoSProfile(depth=POLL_DEPTH, reliability=Reliability.BEST_EFFORT)
        self.odom_sub = node.create_polled_subscription(Odometry, "odom", polled)
        # the aggregated diagnostics (1 Hz), read when asked (`diagnostics`)
        # the robot's aggregator: /diagnostics_agg in the sim, /<robot>/diagnostics_agg in a
        # fleet or on a station (robot.yaml runs one in each robot's namespace)
        self.diag_sub = node.create_polled_subscription(DiagnosticArray, "diagnostics_agg", 1)
        self._diag: dict[str, DiagnosticStatus] = {}
        node.create_subscription(BatteryState, "battery_state", self.on_battery, 10)
        node.create_subscription(PoseWithCovarianceStamped, "robot_pose", self.on_pose, 10)
        node.create_subscription(Twist, "cmd_vel", self.on_cmd_vel, 10)
        node.create_subscription(Log, "/rosout", self.on_log, 100)
        self.tts_pub = node.create_publisher(String, "tts", QOS_LATCHED)
        try:
            chassis_state: Any = lookup_type("zenros_msgs/ChassisState")
        except UnknownTypeError:
            chassis_state = None
        if chassis_state is not None:
            node.create_subscription(chassis_state, "chassis/state", self.on_chassis, 10)
        core.native = self.publish_native
        node.create_subscription(GalileoNativeCmds, "galileo/cmds", self.on_cmds, 50)
        # Wall time whatever the node's clock: outside clients (the status WebSocket, Modbus,
        # the serial bridge) see 30 Hz at any sim speed, and the dead-man timeout is theirs.
        wall = SteadyClock()
        node.create_timer(1.0 / rate, self.on_status_tick, clock=wall)
        # The dead-man ticks only while someone drives (20 Hz a robot, for nothing at rest):
        # it stops when the dead-man has nothing to say, and a command starts it again, on
        # the executor's loop, where the ticks run (so a stop and a start never cross).
        self._deadman_timer = node.create_timer(DEADMAN_PERIOD, self.on_deadman_tick,
                                                clock=wall)
        executor = node.context.executor
        core.deadman.on_arm = lambda: executor.call_soon(self._rearm)

    # ------------------------------------------------------------------ in

    def poll(self) -> None:
        """Take the odometry that arrived since the last status tick."""
        odom = self.odom_sub.take()
        for at in odom.arrivals:
            self.core.state.note_odom(at)
        if odom.count:
            self.seen["odom"] = odom.arrivals[-1]
        if odom.latest is not None:
            self.on_odom(odom.latest, odom.arrivals[-1])

    def diagnostics(self, within: float = 5.0) -> dict[str, DiagnosticStatus] | None:
        """The aggregator's tree (``diagnostics_agg``) by status name, or None when none
        came in the last ``within`` seconds (no aggregator running)."""
        got = self.diag_sub.take()
        if got.latest is not None:
            self._diag = {s.name: s for s in got.latest.status}
            self.seen["diagnostics_agg"] = got.arrivals[-1]
        return self._diag if self.fresh("diagnostics_agg", within) else None

    def on_log(self, msg: Log) -> None:
        level = {10: "DEBUG", 20: "INFO", 30: "WARN", 40: "ERROR", 50: "FATAL"}.get(
            msg.level, str(msg.level))
        self.log.append(f"[{level}] [{msg.stamp.sec}.{msg.stamp.nanosec // 1_000_000:03d}] "
                        f"[{msg.name}]: {msg.msg}")

    def fresh(self, topic: str, within: float = 2.0) -> bool:
        """Whether ``topic`` delivered a message in the last ``within`` seconds."""
        at = self.seen.get(topic)
        return at is not None and time.monotonic() - at <= within

    def on_odom(self, msg: Odometry, at: float | None = None) -> None:
        """The newest odometry (``at``: when it was sent, monotonic; default now)."""
        if at is None:
            self.seen["odom"] = at = time.monotonic()
            self.core.state.note_odom(at)
        s = self.core.state
        s.speed_x = msg.twist.twist.linear.x
        s.speed_theta = msg.twist.twist.angular.z

    def on_battery(self, msg: BatteryState) -> None:
        self.seen["battery_state"] = time.monotonic()
        s = self.core.state
        s.voltage = msg.voltage
        pct = msg.percentage
        s.battery_percent = pct * 100.0 if pct <= 1.0 else pct
        s.charged = msg.power_supply_status == POWER_SUPPLY_STATUS_FULL and s.charging
        if msg.power_supply_status == POWER_SUPPLY_STATUS_CHARGING:
            s.charging = True

    def on_chassis(self, msg: Any) -> None:
        self.seen["chassis/state"] = time.monotonic()
        s = self.core.state
        s.charging = bool(getattr(msg, "charging", False))
        s.estop = bool(getattr(msg, "estop", False))
        if not s.charging:
            s.charged = False

    def on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        p = msg.pose.pose
        o = p.orientation
        s = self.core.state
        s.pose = (p.position.x, p.position.y, yaw_from_msg(o))
        s.pose_time = time.monotonic()

    def on_cmd_vel(self, msg: Twist) -> None:
        s = self.core.state
        s.control_x = msg.linear.x
        s.control_theta = msg.angular.z
        self._control_at = time.monotonic()

    def on_cmds(self, msg: GalileoNativeCmds) -> None:
        if self.on_native is not None:
            self.on_native(bytes(msg.data[:msg.length]))

    # ------------------------------------------------------------------ out

    def on_status_tick(self) -> None:
        self.poll()
        s = self.core.state
        if (s.control_x or s.control_theta) and time.monotonic() - self._control_at > CONTROL_STALE:
            s.control_x = s.control_theta = 0.0
        self.status_pub.publish(self.core.refresh())

    def on_deadman_tick(self) -> None:
        cmd = self.core.deadman.tick()
        if cmd is None:
            self._deadman_timer.cancel()
            return
        x, y, w = cmd
        self.cmd_vel_pub.publish(Twist(linear=Vector3(x=x, y=y), angular=Vector3(z=w)))

    def _rearm(self) -> None:
        """A command after a quiet spell: publish it now, then tick every period."""
        if self.node.closed:
            return
        self._deadman_timer.reset()
        self.on_deadman_tick()

    def publish_native(self, data: bytes) -> None:
        """Publish native command bytes on ``galileo/cmds`` (docs/robot-api.md §12.1)."""
        now = time.time_ns()
        header = GalileoHeader(frame_id="")
        header.stamp.secs, header.stamp.nsecs = divmod(now, 1_000_000_000)
        self.cmds_pub.publish(GalileoNativeCmds(header=header, length=len(data),
                                                data=list(data)))
