"""`RobotState`: what the gateway knows of the robot, and the docs/robot-api.md §4 GalileoStatus
composed from it."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from zenros.msgs.galileo_msgs import GalileoHeader, GalileoStamp, GalileoStatus

__all__ = ["GoalState", "RobotState", "compose_status", "f32", "system_status_name"]

POSE_STALE = 2.0  # seconds without a map pose before localisation counts as lost
_F32_MAX = 3.4028234663852886e38


def f32(v: float) -> float:
    """``v`` packable as a float32: beyond its range, ±infinity (as a float32 cast rounds);
    the Modbus and serial doors send GalileoStatus fields through it."""
    return math.copysign(math.inf, v) if abs(v) > _F32_MAX else v


@dataclass
class GoalState:
    """The current navigation goal as §4 reports it."""

    num_id: int = -1          # nav-point index; -2 goal without an id; -1 none
    status: int = 0           # 0 free, 1 working, 2 paused, 3 error, -1 invalid
    distance: float = -1.0    # m to the goal, -1 unknown
    angle_status: int = -1    # 0 turning, 1 done, 2 error, -1 invalid


@dataclass
class RobotState:
    """Latest values from the robot's topics; each field is replaced whole (thread-safe
    enough for readers that take a consistent-enough snapshot 30 times a second)."""

    speed_x: float = 0.0
    speed_theta: float = 0.0
    control_x: float = 0.0
    control_theta: float = 0.0
    voltage: float = 0.0
    battery_percent: float = 0.0     # 0..100
    charging: bool = False
    charged: bool = False
    estop: bool = False              # the chassis's e-stop is engaged (chassis/state)
    docking_phase: int = 0           # 3 finding, 4 docking, 5 error while a charge runs
    pose: tuple[float, float, float] | None = None
    pose_time: float = 0.0           # time.monotonic() of the last map pose
    odom_times: list[float] = field(default_factory=list)
    nav_open: bool = False
    mapping: bool = False
    busy: bool = False
    looping: bool = False
    goal: GoalState = field(default_factory=GoalState)

    def odom_rate(self, now: float | None = None, window: float = 2.0) -> int:
        """Odometry messages per second over the last ``window`` seconds."""
        now = time.monotonic() if now is None else now
        recent = [t for t in self.odom_times if now - t <= window]
        return round(len(recent) / window)

    def note_odom(self, now: float | None = None) -> None:
        now = time.monotonic() if now is None else now
        times = self.odom_times
        times.append(now)
        if len(times) > 400:
            del times[: len(times) - 200]


def _charge_status(s: RobotState) -> int:
    if s.charged:
        return 2
    if s.charging:
        return 1
    return s.docking_phase


def compose_status(s: RobotState, seq: int, stamp_ns: int, now: float | None = None
                   ) -> GalileoStatus:
    """The §4 message for the current state (``now``: time.monotonic(), for pose age)."""
    now = time.monotonic() if now is None else now
    fresh = s.pose is not None and now - s.pose_time <= POSE_STALE
    if not s.nav_open:
        visual = -1
    elif s.pose is None:
        visual = 0
    else:
        visual = 1 if fresh else 2
    x, y, a = s.pose if s.pose is not None else (-1.0, -1.0, -1.0)
    g = s.goal
    secs, nsecs = divmod(stamp_ns, 1_000_000_000)
    return GalileoStatus(
        header=GalileoHeader(seq=seq & 0xFFFFFFFF, stamp=GalileoStamp(secs=secs, nsecs=nsecs),
                             frame_id="map"),
        navStatus=int(s.nav_open), visualStatus=visual, mapStatus=int(s.mapping),
        gcStatus=0, gbaStatus=0, chargeStatus=_charge_status(s), loopStatus=int(s.looping),
        power=s.voltage, targetNumID=g.num_id, targetStatus=g.status,
        targetDistance=g.distance, angleGoalStatus=g.angle_status,
        controlSpeedX=s.control_x, controlSpeedTheta=s.control_theta,
        currentSpeedX=s.speed_x, currentSpeedTheta=s.speed_theta,
        currentPosX=x, currentPosY=y, currentAngle=a, busyStatus=int(s.busy),
    )


def system_status_name(st: GalileoStatus) -> str:
    """§4 impl. note: mapStatus → Mapping, navStatus → Navigating, busyStatus → Busy, else Free."""
    if st.mapStatus == 1:
        return "Mapping"
    if st.navStatus == 1:
        return "Navigating"
    if st.busyStatus == 1:
        return "Busy"
    return "Free"
