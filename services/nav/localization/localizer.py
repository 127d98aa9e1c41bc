"""Localizer: the robot's pose in ``map`` and the map→odom correction.

The estimate is ``map_T_odom * odom_T_base``. Modes:

- ``ground_truth`` (the simulator's default): each ``sim/ground_truth`` sample sets
  ``map_T_odom = map_T_base(true) * inverse(odom_T_base)`` with the odometry sample of the
  nearest stamp, so the estimate is exact even when odometry drifts.
- ``odometry``: ``map_T_odom`` stays as the last initial pose set it (dead reckoning).
- ``scan_match``: as ``odometry``, and each matched scan (`correct`) pulls ``map_T_odom``
  toward the pose the scan matcher found. It starts at the identity (the robot starting at
  odom's origin, the map origin in the simulator) unless an initial pose is given.

`set_pose` (``initialpose``) puts the robot at a pose now; in ``ground_truth`` mode it
switches to ``odometry``, since the truth would overwrite it at the next sample. In
``scan_match`` mode a pose given (`set_pose`, `set_map_to_odom`) may be off by more than the
tracking window: ``relocalize`` asks the next match to search wide round it.

While another node owns ``map -> odom`` (nav's mapping mode: the SLAM node), `follow` takes
its transform as it is (``external``): neither the truth nor the matcher nor an initial
pose moves it then.
"""

from __future__ import annotations

import threading
from collections import deque
from typing import Literal

from zenros.se2 import Pose2, angle_diff

__all__ = ["MODES", "Localizer", "Mode"]

Mode = Literal["ground_truth", "odometry", "scan_match"]
MODES: tuple[Mode, ...] = ("ground_truth", "odometry", "scan_match")


class Localizer:
    """Fuses odometry with ground truth or an initial pose; thread-safe."""

    def __init__(self, mode: Mode = "ground_truth", history: int = 200) -> None:
        if mode not in MODES:
            raise ValueError(f"unknown localization mode {mode!r}; valid: {', '.join(MODES)}")
        self.mode: Mode = mode
        self.map_to_odom = Pose2()
        self._odom: deque[tuple[int, Pose2]] = deque(maxlen=history)
        self._lock = threading.Lock()
        self.localized = mode == "scan_match"
        self.odom_stamp_ns = 0
        self.corrections = 0
        self._pending_truth: tuple[int, Pose2] | None = None
        # the last truth applied: (true pose, odometry, the map_to_odom they gave)
        self._applied: tuple[Pose2, Pose2, Pose2] | None = None
        self.external = False
        self.relocalize = False

    def set_mode(self, mode: str) -> None:
        if mode not in MODES:
            raise ValueError(f"unknown localization mode {mode!r}; valid: {', '.join(MODES)}")
        self.mode = mode
        if mode == "scan_match":
            self.localized = True

    def set_external(self, on: bool) -> None:
        """``map -> odom`` comes from elsewhere (`follow`) while ``on``; unknown until then."""
        with self._lock:
            self.external = on
            self._pending_truth = None
            if on:
                self.localized = False
            self.relocalize = False

    def follow(self, map_to_odom: Pose2) -> None:
        """The transform the owner of ``map -> odom`` published (only while external)."""
        with self._lock:
            if self.external:
                self.map_to_odom = map_to_odom
                self.localized = True

    def set_map_to_odom(self, map_to_odom: Pose2) -> None:
        """Where odometry's frame is in the map (a map just built, where mapping left the
        robot); in ``scan_match`` mode the next match searches wide round it."""
        with self._lock:
            self.map_to_odom = map_to_odom
            self.localized = True
            self.relocalize = self.mode == "scan_match"

    def on_odom(self, stamp_ns: int, odom_base: Pose2) -> None:
        with self._lock:
            if self._odom and stamp_ns < self._odom[-1][0]:
                self._odom.clear()  # time went back (sim restart): start over
            self._odom.append((stamp_ns, odom_base))
            self.odom_stamp_ns = stamp_ns
            pending = self._pending_truth
            if pending is not None and pending[0] <= stamp_ns:
                self._pending_truth = None
                if self.mode == "ground_truth" and not self.external:
                    self._apply_truth(*pending)

    def _odom_at(self, stamp_ns: int) -> Pose2 | None:
        """The odometry sample nearest ``stamp_ns`` (searched from the newest: the truth
        usually carries the latest odometry's stamp)."""
        if not self._odom:
            return None
        best = self._odom[-1]
        if best[0] == stamp_ns:  # the usual case: the truth of the newest odometry's stamp
            return best[1]
        for sample in reversed(self._odom):
            if abs(sample[0] - stamp_ns) < abs(best[0] - stamp_ns):
                best = sample
            if sample[0] <= stamp_ns:
                break
        return best[1]

    def on_ground_truth(self, stamp_ns: int, map_base: Pose2) -> None:
        """The true pose at ``stamp_ns``; used once the odometry of that stamp is in (it
        may arrive after the truth), so the two always describe the same instant."""
        if self.mode != "ground_truth" or self.external:
            return
        with self._lock:
            if not self._odom or self._odom[-1][0] < stamp_ns:
                self._pending_truth = (stamp_ns, map_base)
                return
            self._apply_truth(stamp_ns, map_base)

    def _apply_truth(self, stamp_ns: int, map_base: Pose2) -> None:
        odom = self._odom_at(stamp_ns)
        if odom is None:
            return
        last = self._applied  # at rest the same poses come again: nothing to work out
        if (last is None or last[0] is not map_base or last[1] is not odom
                or last[2] is not self.map_to_odom):
            self.map_to_odom = map_base * odom.inverse()
            self._applied = (map_base, odom, self.map_to_odom)
        self.localized = True

    def covers(self, stamp_ns: int) -> bool:
        """True once odometry at or after ``stamp_ns`` has arrived."""
        with self._lock:
            return bool(self._odom) and self._odom[-1][0] >= stamp_ns

    def pose_at(self, stamp_ns: int) -> Pose2 | None:
        """The estimate at the odometry sample nearest ``stamp_ns``."""
        with self._lock:
            odom = self._odom_at(stamp_ns)
            return None if odom is None or not self.localized else self.map_to_odom * odom

    def correct(self, stamp_ns: int, map_base: Pose2, gain: float = 0.5) -> None:
        """Move map→odom by ``gain`` of the way to where ``map_base`` (the robot at
        ``stamp_ns``, found by the scan matcher) puts it."""
        with self._lock:
            odom = self._odom_at(stamp_ns)
            if odom is None or self.mode != "scan_match" or self.external:
                return
            self.relocalize = False
            target = map_base * odom.inverse()
            cur = self.map_to_odom
            self.map_to_odom = Pose2(cur.x + gain * (target.x - cur.x),
                                     cur.y + gain * (target.y - cur.y),
                                     cur.theta + gain * angle_diff(target.theta, cur.theta))
            self.corrections += 1

    def set_pose(self, map_base: Pose2) -> None:
        """Put the robot at ``map_base`` now (``initialpose``)."""
        with self._lock:
            if self.external:
                return
            odom = self._odom[-1][1] if self._odom else Pose2()
            self.map_to_odom = map_base * odom.inverse()
            self.localized = True
            if self.mode == "ground_truth":
                self.mode = "odometry"
            self.relocalize = self.mode == "scan_match"

    def set_pose_at(self, stamp_ns: int, map_base: Pose2) -> bool:
        """Put the robot at ``map_base`` as of ``stamp_ns`` (a fix from a scan of that
        stamp), paired with the odometry sample nearest it, so motion since then is kept.
        The mode stays (in ``ground_truth`` the next truth sample overrides the fix).
        False when there is no odometry yet or another node owns ``map -> odom``."""
        with self._lock:
            odom = self._odom_at(stamp_ns)
            if odom is None or self.external:
                return False
            self.map_to_odom = map_base * odom.inverse()
            self.localized = True
            self.relocalize = False
            return True

    def pose(self) -> Pose2 | None:
        """The robot in ``map`` (None before the first odometry and localisation)."""
        with self._lock:
            if not self._odom or not self.localized:
                return None
            return self.map_to_odom * self._odom[-1][1]
