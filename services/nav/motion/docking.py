"""Dock and Undock: drive onto the charger and off it (opennav_docking's procedure).

Docking: navigate to the staging pose (``staging_offset`` metres behind the dock pose
along its heading), drive straight onto the dock pose under a simple pose controller
(no costmap: the dock sits against a wall), stop within ``docking_threshold`` or when the
chassis reports ``docked``, then wait for the battery to charge. Failing to charge within
``wait_charge_timeout`` backs off to the staging pose and retries, up to ``max_retries``.
Undocking drives straight back to the staging distance.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from zenros.msgs.nav2_msgs import DockRobotFeedback as DockState
from zenros.msgs.nav2_msgs import DockRobotResult as DockCodes
from zenros.msgs.nav2_msgs import UndockRobotResult as UndockCodes
from zenros.se2 import Pose2, angle_diff

from .behavior import Behavior, Sense
from .navigate import Navigate

__all__ = ["Dock", "DockParams", "Undock", "staging_pose"]


@dataclass(frozen=True)
class DockParams:
    """Docking server and SimpleChargingDock parameters (their defaults where they exist)."""

    staging_offset: float = 0.7
    docking_threshold: float = 0.05
    approach_speed: float = 0.15
    approach_timeout: float = 30.0
    wait_charge_timeout: float = 5.0
    max_retries: int = 3
    use_battery_status: bool = True
    undock_speed: float = 0.15


def staging_pose(dock: Pose2, offset: float) -> Pose2:
    """The pose ``offset`` metres in front of the dock, facing it (the dock's heading)."""
    return Pose2(dock.x - offset * math.cos(dock.theta), dock.y - offset * math.sin(dock.theta),
                 dock.theta)


class Dock(Behavior):
    """Dock at ``dock`` (map pose the robot ends at); ``make_nav`` builds the staging leg."""

    name = "dock"

    def __init__(self, dock: Pose2, params: DockParams,
                 make_nav: Callable[[Pose2], Navigate], navigate_to_staging: bool = True,
                 max_staging_time: float = 1000.0) -> None:
        super().__init__()
        self.dock, self.p = dock, params
        self.staging = staging_pose(dock, params.staging_offset)
        self.make_nav = make_nav
        self.max_staging_time = max_staging_time
        self.retries = 0
        self.state = DockState.NAV_TO_STAGING_POSE if navigate_to_staging else DockState.CONTROLLING
        self._nav: Navigate | None = None
        self._phase_t0: float | None = None

    def _enter(self, state: int, now: float) -> None:
        self.state, self._phase_t0 = state, now

    def tick(self, s: Sense) -> tuple[float, float]:
        if self._phase_t0 is None:
            self._phase_t0 = s.now
            if s.docked and (s.charging or not self.p.use_battery_status):
                return self.finish(True)
        if s.pose is None:
            return 0.0, 0.0
        if self.state == DockState.NAV_TO_STAGING_POSE:
            return self._to_staging(s)
        if self.state == DockState.CONTROLLING:
            return self._approach(s)
        if self.state == DockState.WAIT_FOR_CHARGE:
            return self._wait_charge(s)
        return self._back_off(s)  # RETRY

    def _to_staging(self, s: Sense) -> tuple[float, float]:
        if self._nav is None:
            self._nav = self.make_nav(self.staging)
        v, w = self._nav.step(s)
        assert self._phase_t0 is not None
        if s.now - self._phase_t0 > self.max_staging_time:
            return self.finish(False, DockCodes.FAILED_TO_STAGE,
                               f"staging took longer than {self.max_staging_time} s")
        if self._nav.done.is_set():
            nav, self._nav = self._nav, None
            if not nav.succeeded:
                return self.finish(False, DockCodes.FAILED_TO_STAGE,
                                   f"could not reach the staging pose: {nav.error_msg}")
            self._enter(DockState.CONTROLLING, s.now)
            return 0.0, 0.0
        return v, w

    def _approach(self, s: Sense) -> tuple[float, float]:
        assert s.pose is not None and self._phase_t0 is not None
        d = s.pose.distance(self.dock)
        if s.docked or d <= self.p.docking_threshold:
            self._enter(DockState.WAIT_FOR_CHARGE, s.now)
            return 0.0, 0.0
        if s.now - self._phase_t0 > self.p.approach_timeout:
            return self._retry(s, DockCodes.FAILED_TO_CONTROL, "could not reach the dock")
        # aim at the dock point while far, hold the dock's heading when close
        local = s.pose.inverse().apply(self.dock.x, self.dock.y)
        if local[0] < -0.02:  # overshot: back up along the heading
            return -0.05, 0.0
        bearing = math.atan2(local[1], max(local[0], 1e-6))
        heading = angle_diff(self.dock.theta, s.pose.theta)
        target = bearing if d > 0.15 else heading
        w = max(-0.8, min(0.8, 2.0 * target))
        v = min(self.p.approach_speed, max(0.03, 0.8 * local[0])) if abs(target) < 0.5 else 0.0
        return v, w

    def _wait_charge(self, s: Sense) -> tuple[float, float]:
        assert self._phase_t0 is not None
        if s.charging or not self.p.use_battery_status:
            return self.finish(True)
        if s.now - self._phase_t0 > self.p.wait_charge_timeout:
            return self._retry(s, DockCodes.FAILED_TO_CHARGE, "docked but not charging")
        return 0.0, 0.0

    def _retry(self, s: Sense, code: int, msg: str) -> tuple[float, float]:
        if self.retries >= self.p.max_retries:
            return self.finish(False, code, f"{msg} after {self.retries} retries")
        self.retries += 1
        self._enter(DockState.RETRY, s.now)
        return 0.0, 0.0

    def _back_off(self, s: Sense) -> tuple[float, float]:
        assert s.pose is not None and self._phase_t0 is not None
        if s.pose.distance(self.dock) >= self.p.staging_offset * 0.8 \
                or s.now - self._phase_t0 > self.p.approach_timeout:
            self._enter(DockState.NAV_TO_STAGING_POSE, s.now)
            return 0.0, 0.0
        return -self.p.undock_speed, 0.0


class Undock(Behavior):
    """Back straight off the dock until ``staging_offset`` away from it."""

    name = "undock"

    def __init__(self, dock: Pose2 | None, params: DockParams, timeout: float) -> None:
        super().__init__()
        self.dock, self.p, self.timeout = dock, params, timeout
        self._t0: float | None = None
        self._start: Pose2 | None = None

    def tick(self, s: Sense) -> tuple[float, float]:
        if s.pose is None:
            return 0.0, 0.0
        if self._t0 is None:
            self._t0, self._start = s.now, s.pose
        ref = self.dock or self._start
        assert ref is not None
        if s.pose.distance(ref) >= self.p.staging_offset - 0.05 and not s.docked:
            return self.finish(True)
        if s.now - self._t0 > self.timeout:
            return self.finish(False, UndockCodes.TIMEOUT,
                               f"still on the dock after {self.timeout} s")
        return -self.p.undock_speed, 0.0
