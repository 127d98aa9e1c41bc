"""`RobotLink`: the `Robot` the tasks service drives, over zenros (nav actions and services).

``navigate_to_pose`` and ``dock_robot`` (nav2_msgs actions), nav points and map switching
(zenros_msgs services of nav), ``battery_state`` for charge levels, ``tts`` for speech.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import Any, Final

from zenros.action import ActionClient, GoalStatus
from zenros.errors import ActionServerUnavailableError, ZenrosError
from zenros.maps.maproute import Link, links_of
from zenros.msgs.geometry_msgs import (
    Point,
    Pose,
    PoseStamped,
    PoseWithCovarianceStamped,
    Quaternion,
)
from zenros.msgs.nav2_msgs import DockRobot, DockRobotGoal, NavigateToPose, NavigateToPoseGoal
from zenros.msgs.sensor_msgs import BatteryState
from zenros.msgs.std_msgs import Header, String
from zenros.msgs.zenros_msgs.nav import (
    GetCurrentMap,
    GetCurrentMapRequest,
    GetNavPoints,
    GetNavPointsRequest,
    ListPaths,
    ListPathsRequest,
    ListPointConnections,
    ListPointConnectionsRequest,
    RelocalizeLandmarks,
    RelocalizeLandmarksRequest,
    SwitchMap,
    SwitchMapRequest,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.se2 import angle_diff
from zenros.tf.quaternion import quaternion_from_yaw, yaw_from_quaternion

from .elevator_link import ElevatorLink
from .map_exchange import MapExchange
from .pass_through import PassThrough
from .robot import Feedback, Outcome

__all__ = ["RobotLink"]

POLL: Final = 0.02
SERVER_WAIT: Final = 5.0
RELOCALISED: Final = (0.05, 0.05)  # m, rad: robot_pose this close to an initial pose


def cancel_and_wait(handle: Any, timeout: float) -> None:
    """Cancel a goal and wait (up to ``timeout`` s in all) for its end. A goal sent an
    instant ago may not be known to its server yet: a cancel that overtakes it is refused
    (unknown goal id) and the goal would run to its end (a task stopped right after a resume
    went on driving). So a refused cancel is asked again once the goal is accepted."""
    deadline = time.monotonic() + timeout
    try:
        while True:
            known = handle.accepted is not None  # the server had answered the goal
            if handle.cancel(max(0.0, deadline - time.monotonic())) or handle.done or known:
                break  # canceling, ended, or refused by a server that knew the goal
            if not handle.wait_accepted(max(0.0, deadline - time.monotonic())):
                break  # rejected: nothing runs
        handle.result(max(0.0, deadline - time.monotonic()))
    except ZenrosError:
        pass


class RobotLink:
    """Implements `Robot` for a tasks node; every call is bounded in time and cancellable."""

    def __init__(self, node: Node, reconnect: float = 30.0) -> None:
        self.node = node
        self.reconnect = reconnect
        self.nav = ActionClient(node, NavigateToPose, "navigate_to_pose")
        self.dock = ActionClient(node, DockRobot, "dock_robot")
        self.nav_points = node.create_client(GetNavPoints, "get_nav_points")
        self.paths = node.create_client(ListPaths, "list_paths")
        self.current_map_srv = node.create_client(GetCurrentMap, "map_server/current_map")
        self.switch = node.create_client(SwitchMap, "switch_map")
        self.connections = node.create_client(ListPointConnections, "list_point_connections")
        self.landmarks = node.create_client(RelocalizeLandmarks, "relocalize_landmarks")
        self.initialpose = node.create_publisher(PoseWithCovarianceStamped, "initialpose", 10)
        self._pose: tuple[float, float, float] | None = None
        self._pose_sub: Any = None  # robot_pose, only while a map switch relocalises
        self.tts = node.create_publisher(String, "tts", QOS_LATCHED)
        self.battery: float | None = None
        self.charging = False
        node.create_subscription(BatteryState, "battery_state", self._on_battery)
        self.maps = MapExchange(node)
        self.elevators: ElevatorLink | None = None  # the tasks node sets it for a building
        self.passing = PassThrough(self.nav, self.now, cancel_and_wait)

    def _on_battery(self, msg: BatteryState) -> None:
        self.battery = float(msg.percentage)
        self.charging = msg.power_supply_status in (BatteryState.POWER_SUPPLY_STATUS_CHARGING,
                                                    BatteryState.POWER_SUPPLY_STATUS_FULL)

    def _on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        p = msg.pose.pose
        q = p.orientation
        self._pose = (p.position.x, p.position.y, yaw_from_quaternion((q.x, q.y, q.z, q.w)))

    def now(self) -> float:
        return self.node.now().to_sec()

    def pose(self) -> tuple[float, float, float] | None:
        """The latest ``robot_pose``: subscribed on the first call (waiting up to
        SERVER_WAIT for a sample) until the next `relocalise` ends."""
        if self._pose_sub is None:
            self._pose = None
            self._pose_sub = self.node.create_subscription(PoseWithCovarianceStamped,
                                                           "robot_pose", self._on_pose)
            end = time.monotonic() + SERVER_WAIT
            while self._pose is None and time.monotonic() < end:
                threading.Event().wait(POLL)
        return self._pose

    def current_map(self) -> str:
        try:
            return str(self.current_map_srv.call(GetCurrentMapRequest(),
                                                 timeout=SERVER_WAIT).name)
        except ZenrosError as exc:
            raise LookupError(f"cannot read the current map: {exc}") from exc

    def point_connections(self) -> list[Link]:
        try:
            res = self.connections.call(ListPointConnectionsRequest(), timeout=SERVER_WAIT)
        except ZenrosError as exc:
            raise LookupError(f"cannot read the point connections: {exc}") from exc
        return links_of(res.points, res.connections)

    def relocalise_landmarks(self) -> Outcome:
        try:
            res = self.landmarks.call(RelocalizeLandmarksRequest(), timeout=SERVER_WAIT)
        except ZenrosError as exc:
            return Outcome("error", f"relocalise on landmarks: {exc}")
        if not res.success:
            return Outcome("fail", f"relocalise on landmarks: {res.message}")
        return Outcome("complete", f"relocalised on {len(res.ids)} reflector(s), "
                                   f"{res.shift:.2f} m / {math.degrees(res.turn):.1f} deg")

    def relocalise(self, x: float, y: float, theta: float) -> Outcome:
        msg = PoseWithCovarianceStamped(header=Header(frame_id="map"))
        msg.pose.pose = _pose(x, y, theta).pose
        self.pose()
        try:
            end = time.monotonic() + SERVER_WAIT
            while time.monotonic() < end:
                self.initialpose.publish(msg)  # until nav has it (a new link may drop one)
                threading.Event().wait(POLL)
                p = self._pose
                if p is not None and math.hypot(p[0] - x, p[1] - y) <= RELOCALISED[0] \
                        and abs(angle_diff(p[2], theta)) <= RELOCALISED[1]:
                    return Outcome("complete",
                                   f"relocalised at ({x:.2f}, {y:.2f}, {theta:.2f})")
        finally:
            self.node.destroy(self._pose_sub)
            self._pose_sub = None
        return Outcome("error", f"nav did not take the initial pose ({x:.2f}, {y:.2f}, "
                                f"{theta:.2f}) within {SERVER_WAIT:g} s")

    def nav_point(self, index: int, map_name: str, path_name: str) -> tuple[float, float, float]:
        try:
            if not path_name:
                path_name, map_name = self._only_path(map_name)
            points = self.nav_points.call(GetNavPointsRequest(map_name=map_name,
                                                              path_name=path_name),
                                          timeout=SERVER_WAIT).points
        except ZenrosError as exc:
            raise LookupError(f"cannot read nav points: {exc}") from exc
        if not 0 <= index < len(points):
            raise LookupError(f"no nav point {index}: path {path_name!r} has {len(points)}"
                              + (f" (0..{len(points) - 1})" if points else ""))
        p = points[index]
        return p.x, p.y, p.theta

    def _only_path(self, map_name: str) -> tuple[str, str]:
        if not map_name:
            map_name = self.current_map_srv.call(GetCurrentMapRequest(),
                                                 timeout=SERVER_WAIT).name
        refs = self.paths.call(ListPathsRequest(map_name=map_name), timeout=SERVER_WAIT).paths
        if len(refs) != 1:
            names = ", ".join(r.path_name for r in refs) or "none"
            raise LookupError(f"give the nav_action a 'path': map {map_name!r} has"
                              f" {len(refs)} paths ({names})")
        return refs[0].path_name, map_name

    def navigate(self, x: float, y: float, theta: float, timeout: float,
                 feedback: Callable[[Feedback], None],
                 cancelled: Callable[[], bool]) -> Outcome:

        def on_feedback(msg: Any) -> None:
            fb = msg.feedback
            p = fb.current_pose.pose
            q = p.orientation
            feedback(Feedback(p.position.x, p.position.y,
                              yaw_from_quaternion((q.x, q.y, q.z, q.w)), fb.distance_remaining))

        goal = NavigateToPoseGoal(pose=_pose(x, y, theta))
        return self._run(self.nav, goal, on_feedback, timeout, cancelled,
                         f"navigate to ({x:.2f}, {y:.2f}, {theta:.2f})")

    def pass_through(self, x: float, y: float, theta: float, radius: float, timeout: float,
                     feedback: Callable[[Feedback], None],
                     cancelled: Callable[[], bool]) -> Outcome:
        return self.passing.run(NavigateToPoseGoal(pose=_pose(x, y, theta)), radius, timeout,
                                feedback, cancelled)

    def stop_passing(self) -> None:
        self.passing.stop()

    def charge(self, pose: tuple[float, float, float] | None, level: float, timeout: float,
               cancelled: Callable[[], bool]) -> Outcome:
        goal = DockRobotGoal(use_dock_id=pose is None, navigate_to_staging_pose=True)
        if pose is not None:
            goal.dock_pose = _pose(*pose)
        start = self.now()
        out = self._run(self.dock, goal, None, timeout, cancelled, "dock")
        if out.name != "complete" or level <= 0:
            return out
        while self.battery is None or self.battery < level:
            if cancelled():
                return Outcome("preempted")
            if timeout > 0 and self.now() - start > timeout:
                return Outcome("error", f"battery at {self.battery or 0:.0%}, not {level:.0%},"
                                        f" after {timeout:g} s")
            threading.Event().wait(POLL)
        return Outcome("complete", f"charged to {self.battery:.0%}")

    def _run(self, client: ActionClient, goal: Any, on_feedback: Any, timeout: float,
             cancelled: Callable[[], bool], what: str) -> Outcome:
        """Run one goal to its end. A server that goes away (a link flap, a respawn) is
        waited for up to ``reconnect`` seconds and the goal sent again, as a robot's task
        should outlive a short outage; past that the action ends in ERROR."""
        start = self.now()
        lost_since: float | None = None
        while True:
            budget = self.reconnect - (time.monotonic() - lost_since if lost_since else 0.0)
            if not self._await_server(client, cancelled, max(budget, 0.0)):
                if cancelled():
                    return Outcome("preempted")
                return Outcome("error", f"{what}: no {client.name} server"
                                        f" (waited {self.reconnect:g} s)")
            handle = client.send_goal_async(goal, on_feedback)
            while not handle.done:
                if cancelled() or (timeout > 0 and self.now() - start > timeout):
                    cancel_and_wait(handle, SERVER_WAIT)
                    if cancelled():
                        return Outcome("preempted")
                    return Outcome("error", f"{what}: not done within {timeout:g} s")
                if handle.accepted:
                    lost_since = None
                threading.Event().wait(POLL)
            try:
                res = handle.result(0)
            except ActionServerUnavailableError as exc:
                res = None
                reason = str(exc)
            except ZenrosError as exc:
                return Outcome("error", f"{what}: {exc}")
            if res is None or (res.status is GoalStatus.LOST and not cancelled()):
                reason = reason if res is None else res.reason
                lost_since = lost_since or time.monotonic()
                if time.monotonic() - lost_since < self.reconnect:
                    self.node.logger.warning("%s: %s; sending the goal again when %s is back",
                                             what, reason, client.name)
                    continue
                return Outcome("error", f"{what}: lost ({reason})")
            break
        if res.status is GoalStatus.SUCCEEDED:
            return Outcome("complete", f"{what}: done")
        msg = getattr(res.result, "error_msg", "") or res.reason
        code = getattr(res.result, "error_code", 0)
        return Outcome("error", f"{what}: {res.status.name.lower()}"
                                + (f" (error {code}: {msg})" if code or msg else ""))

    @staticmethod
    def _await_server(client: ActionClient, cancelled: Callable[[], bool],
                      limit: float) -> bool:
        end = time.monotonic() + limit
        while not client.wait_for_server(0.2):
            if cancelled() or time.monotonic() > end:
                return False
        return True

    def switch_map(self, name: str, path: str, start_index: int) -> Outcome:
        start = None
        if start_index >= 0:
            try:
                start = self.nav_point(start_index, name, path)
            except LookupError as exc:
                return Outcome("error", f"switch to map {name!r}: {exc}")
        try:
            res = self.switch.call(SwitchMapRequest(map_name=name), timeout=SERVER_WAIT)
        except ZenrosError as exc:
            return Outcome("error", f"switch to map {name!r}: {exc}")
        if not res.success:
            return Outcome("error", f"switch to map {name!r}: {res.message}")
        if start is not None:
            out = self.relocalise(*start)
            if out.name != "complete":
                return out
        return Outcome("complete", f"map {name}")

    def battery_percent(self) -> float | None:
        return None if self.battery is None else self.battery * 100.0

    def say(self, text: str) -> None:
        self.tts.publish(String(data=text))

    def upload_map(self, server_id: str) -> Outcome:
        return self.maps.upload(server_id)

    def download_map(self, server_id: str, map_id: str) -> Outcome:
        return self.maps.download(server_id, map_id)


def _pose(x: float, y: float, theta: float) -> PoseStamped:
    qx, qy, qz, qw = quaternion_from_yaw(theta)
    return PoseStamped(header=Header(frame_id="map"),
                       pose=Pose(position=Point(x=x, y=y),
                                 orientation=Quaternion(x=qx, y=qy, z=qz, w=qw)))


