"""`LocalLink`: the tasks service's `RobotLink` plus local moves, IO outputs and actuators.

Local moves go to nav's ``drive_on_heading`` and ``spin`` (nav2_msgs) and
``local_move_target`` (zenros_msgs/LocalMoveTarget) actions; outputs to the chassis's
``chassis/set_io`` service, actuator moves to its ``actuators/move`` (`ActuatorLink`). Each
call is bounded in time and cancellable, as RobotLink's.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, Literal

from zenros.action import ActionClient
from zenros.errors import ZenrosError
from zenros.msgs.builtin_interfaces import Duration
from zenros.msgs.geometry_msgs import Point
from zenros.msgs.nav2_msgs import DriveOnHeading, DriveOnHeadingGoal, Spin, SpinGoal
from zenros.msgs.zenros_msgs.blockly import BlocklyProgram
from zenros.msgs.zenros_msgs.chassis import IoState, SetIo, SetIoRequest
from zenros.msgs.zenros_msgs.nav import LocalMoveTarget, LocalMoveTargetGoal
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.tf.quaternion import quaternion_from_yaw

from .actuator_link import ActuatorLink
from .config_link import ConfigLink
from .launcher import Launcher
from .link import SERVER_WAIT, RobotLink
from .media_link import MediaLink
from .programs import ProgramStore
from .ptz_link import PtzLink
from .robot import Outcome

__all__ = ["LocalLink"]


class LocalLink(RobotLink):
    """Implements `Robot` for a tasks node, local moves, IO and actuators included."""

    def __init__(self, node: Node, reconnect: float = 30.0) -> None:
        super().__init__(node, reconnect)
        self.drive_client = ActionClient(node, DriveOnHeading, "drive_on_heading")
        self.spin_client = ActionClient(node, Spin, "spin")
        self.target_client = ActionClient(node, LocalMoveTarget, "local_move_target")
        self.io = node.create_client(SetIo, "chassis/set_io")
        self.actuators = ActuatorLink(node, SERVER_WAIT)
        self.ptz = PtzLink(node, SERVER_WAIT)
        self.media = MediaLink(node, SERVER_WAIT)
        self.config = ConfigLink(node, SERVER_WAIT)
        self.launcher: Launcher | None = None  # the tasks node's (roslaunch_action)
        self.io_state: IoState | None = None
        self._io_heard = threading.Event()
        self._io_sub: object | None = None  # chassis/io, subscribed at the first read
        self.programs: ProgramStore | None = None  # the tasks node's (Blockly programs)

    def _on_io(self, msg: IoState) -> None:
        self.io_state = msg
        self._io_heard.set()

    def io_levels(self) -> tuple[list[int], list[int], list[int]]:
        if self._io_sub is None:
            self._io_sub = self.node.create_subscription(IoState, "chassis/io", self._on_io,
                                                         QOS_LATCHED)
            self._io_heard.wait(SERVER_WAIT)  # its latched state
        st = self.io_state
        if st is None:
            raise LookupError("no IO state: the chassis has not reported chassis/io")
        return list(st.outputs), list(st.ext_outputs), list(st.ext_inputs)

    def blockly_program(self, program_id: str) -> BlocklyProgram:
        if self.programs is None:
            raise LookupError("this tasks service keeps no Blockly programs")
        return self.programs.get(program_id)

    def move_axis(self, axis: str, mode: int, target: float, speed: float, duration: float,
                  progress: Callable[[float], None],
                  cancelled: Callable[[], bool]) -> Outcome:
        return self.actuators.move(axis, mode, target, speed, duration, progress, cancelled)

    def ptz_move(self, x: float, y: float, zoom: float, progress: Callable[[float], None],
                 cancelled: Callable[[], bool]) -> Outcome:
        return self.ptz.move(x, y, zoom, progress, cancelled)

    def save_media(self, kind: Literal["image", "video", "audio"], topic: str,
                   duration: float, filename: str, progress: Callable[[float], None],
                   cancelled: Callable[[], bool]) -> Outcome:
        return self.media.save(kind, topic, duration, filename, progress, cancelled)

    def change_settings(self, settings: dict[str, Any], check_only: bool = False) -> Outcome:
        return self.config.change(settings, check_only)

    def launch(self, launch_cmd: str, cancelled: Callable[[], bool]) -> tuple[Outcome, str]:
        if self.launcher is None:
            return Outcome("error", "this tasks service runs no launch files"), ""
        return self.launcher.start(launch_cmd, cancelled)

    def stop_launch(self, key: str) -> None:
        if self.launcher is not None:
            self.launcher.stop(key)

    def drive(self, distance: float, speed: float, timeout: float,
              progress: Callable[[float], None], cancelled: Callable[[], bool]) -> Outcome:
        goal = DriveOnHeadingGoal(target=Point(x=distance),
                                  speed=abs(speed) if distance >= 0 else -abs(speed))
        return self._run(self.drive_client, goal,
                         lambda m: progress(m.feedback.distance_traveled), timeout, cancelled,
                         f"drive {distance:.2f} m")

    def spin(self, angle: float, timeout: float, progress: Callable[[float], None],
             cancelled: Callable[[], bool]) -> Outcome:
        return self._run(self.spin_client, SpinGoal(target_yaw=angle),
                         lambda m: progress(m.feedback.angular_distance_traveled), timeout,
                         cancelled, f"spin {angle:.2f} rad")

    def local_move_target(self, x: float, y: float, theta: float, frame_id: str,
                          xy_tolerance: float, yaw_tolerance: float, timeout: float,
                          start_rotate: bool, target_rotate: bool,
                          cancelled: Callable[[], bool]) -> Outcome:
        goal = LocalMoveTargetGoal(xy_tolerance=xy_tolerance, yaw_tolerance=yaw_tolerance,
                                   time_allowance=Duration.from_seconds(timeout),
                                   start_rotate_enable=start_rotate,
                                   target_rotate_enable=target_rotate)
        goal.pose.header.frame_id = frame_id
        goal.pose.pose.position.x, goal.pose.pose.position.y = x, y
        q = goal.pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(theta)
        return self._run(self.target_client, goal, None, 0.0, cancelled,
                         f"local move to ({x:.2f}, {y:.2f}, {theta:.2f}) in {frame_id}")

    def set_io(self, port: int, level: int) -> Outcome:
        try:
            res = self.io.call(SetIoRequest(board="main", port=port, level=level),
                               timeout=SERVER_WAIT)
        except ZenrosError as exc:
            return Outcome("error", f"set IO out{port}: {exc}")
        if not res.success:
            return Outcome("error", f"set IO out{port}: {res.message}")
        return Outcome("complete", f"out{port} = {level}")
