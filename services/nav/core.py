"""NavCore: nav's parts put together (maps, localisation, costmaps, planner, motion).

Everything here is plain Python: the node feeds it sensor data (`on_odom`, `on_scan`,
`on_ground_truth`, `on_battery`, `on_chassis`) and calls `tick` from its control timer;
what goes out (commands, plans, status) is returned or handed to the ``on_plan`` callback.
"""

from __future__ import annotations

import dataclasses
import math
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from zenros.errors import MapError
from zenros.maps import GridMap
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.se2 import Pose2

from .costmap import CostmapParams
from .costmap.live import Costmaps
from .localization.localizer import MODES, Localizer, Mode
from .localization.scanmatch import ScanMatcher
from .maps.mapmeta import MapRecord
from .maps.records import Records
from .maps.saver import GridSaver
from .maps.server import MapServer
from .maps.store import MapStore
from .motion.active import Motion
from .motion.behavior import Behavior, NavParams, Sense
from .motion.controller import ControllerParams
from .motion.docking import DockParams
from .motion.navigate import Codes, Navigate
from .motion.traffic import TrafficGate
from .planning import PlannerParams
from .planning.global_planner import GlobalPlanner, PlanWorker
from .planning.interface import PlannerContext
from .planning.registry import PlannerSpec, build_planners, default_specs

__all__ = ["MappingRefused", "NavConfig", "NavCore"]


class MappingRefused(Exception):
    """A mapping-mode change that cannot be made now (``code``: a zenros ResultCode)."""

    def __init__(self, code: ResultCode, reason: str) -> None:
        super().__init__(reason)
        self.code = code


@dataclass(frozen=True)
class NavConfig:
    """Every tunable of the core, built by the node from its parameters."""

    nav: NavParams = field(default_factory=NavParams)
    controller: ControllerParams = field(default_factory=ControllerParams)
    costmap: CostmapParams = field(default_factory=CostmapParams)
    planner: PlannerParams = field(default_factory=PlannerParams)
    planners: tuple[PlannerSpec, ...] = field(default_factory=default_specs)
    dock: DockParams = field(default_factory=DockParams)
    planner_tolerance: float = 0.25
    localization: Mode = "ground_truth"
    costmap_update_rate: float = 2.0
    local_costmap_size: float = 3.0
    scan_max_points_range: float = 3.0
    scan_match_rate: float = 5.0
    scan_match_gain: float = 0.5
    deterministic: bool = False
    """A deterministic run (docs/replay.md): plans in the caller, no wall-clock budget."""


class NavCore:
    """The state of navigation; the node owns one."""

    def __init__(self, config: NavConfig, maps_root: Any,
                 on_plan: Callable[[np.ndarray], None] | None = None,
                 on_map: Callable[[str, GridMap], None] | None = None) -> None:
        if config.deterministic and config.planner.timeout > 0:  # a wall-clock budget
            config = dataclasses.replace(config, planner=dataclasses.replace(config.planner,
                                                                             timeout=0.0))
        self.config = config
        self.localizer = Localizer(config.localization)
        self.costmaps = Costmaps(config.costmap, config.local_costmap_size,
                                 config.costmap_update_rate)
        self.maps = MapServer(MapStore(maps_root), self._on_map)
        self.records = Records(self.maps, self.localizer.pose, self._on_keepout)
        context = PlannerContext(config.planner, config.nav.robot_radius,
                                 config.planner_tolerance)
        self.planner = GlobalPlanner(config.planner, config.nav.robot_radius,
                                     config.planner_tolerance,
                                     build_planners(config.planners, context))
        self.worker = PlanWorker(self.planner, self.costmaps.snapshot,
                                 threaded=not config.deterministic)
        self.motion = Motion()
        self._on_plan_cb = on_plan
        self._on_map_cb = on_map
        self._lock = threading.Lock()
        self.speed = (0.0, 0.0)
        self.obstacles = np.zeros((0, 2))
        self._scan_key: tuple[Any, ...] | None = None  # the scan `obstacles` came from
        self._scan_ranges = np.zeros(0)
        self.scan_mounts: dict[str, Pose2] = {}
        self.battery: float | None = None
        self._battery_charging = False
        self._chassis_charging = False
        self.docked = False
        self._last_tick: float | None = None
        self.matcher: ScanMatcher | None = None
        self._last_match = -math.inf
        self._pending_scan: tuple[int, np.ndarray] | None = None
        self.saver = GridSaver(self.maps.store, lambda: self.maps.current)
        self.mapping = False
        """Mapping mode: the SLAM node owns ``map`` and ``map -> odom`` (`enter_mapping`)."""
        self.built = False
        """The current map was built by SLAM: localise by scan matching, never the truth."""
        self._mode: Mode = config.localization  # the ``localization`` parameter's mode
        self._start_at: Pose2 | None = None  # map -> odom for the next map (leave_mapping)
        self.match_score: float | None = None  # the last scan match's (0..1)
        self.traffic: TrafficGate | None = None
        """Schedule mode's gate, handed to every navigation (the node sets it)."""

    # ------------------------------------------------------------------ NavTools

    def cost_at(self, x: float, y: float) -> int:
        return self.costmaps.cost_at(x, y)

    def keepout_hit(self, points: np.ndarray) -> bool:
        return self.costmaps.keepout_hit(points)

    def clear_obstacles(self) -> None:
        self.costmaps.clear_obstacles()

    def on_plan(self, xy: np.ndarray) -> None:
        if self._on_plan_cb is not None:
            self._on_plan_cb(xy)

    # ------------------------------------------------------------------ maps

    def _on_map(self, name: str, grid: GridMap) -> None:
        start, self._start_at = self._start_at, None
        if self.mapping:
            return  # chosen for after mapping (`leave_mapping` loads it)
        self.costmaps.set_map(grid, self.maps.store.nav_data(name))
        self.matcher = ScanMatcher(grid)
        try:
            record = self.maps.store.record(name)
        except MapError:
            record = MapRecord()
        was_built, self.built = self.built, record.built_by_slam
        if self.built or was_built:
            self.localizer.set_mode(self._map_mode())
        if self.built and start is None and record.map_to_odom is not None:
            m = record.map_to_odom
            start = Pose2(m.x, m.y, m.theta)
        if start is not None:
            self.localizer.set_map_to_odom(start)
        if self._on_map_cb is not None:
            self._on_map_cb(name, grid)

    def _map_mode(self) -> Mode:
        """The localisation mode on the current map: the parameter's, except that a map
        the robot built is not in the simulator's frame, so no ground truth there."""
        return "scan_match" if self.built and self._mode == "ground_truth" else self._mode

    def set_localization(self, mode: str) -> None:
        """The ``localization`` parameter changed (ValueError for an unknown mode)."""
        if mode not in MODES:
            raise ValueError(f"unknown localization mode {mode!r}; valid: {', '.join(MODES)}")
        self._mode = mode  # type: ignore[assignment]
        self.localizer.set_mode(self._map_mode())

    # ------------------------------------------------------------------ mapping mode

    def enter_mapping(self) -> None:
        """Hand ``map`` and ``map -> odom`` to the SLAM node: the costmaps wait for its map
        (`on_slam_map`), the pose follows its transform (`on_slam_map_to_odom`). Refused
        (`MappingRefused` CONFLICT) while a behaviour drives the robot."""
        if self.mapping:
            return
        active = self.motion.active
        if active is not None:
            raise MappingRefused(ResultCode.CONFLICT, f"navigation is busy ({type(active).__name__.lower()} "
                                    "running): cancel it before mapping")
        self.mapping = True
        self.localizer.set_external(True)
        self.costmaps.drop()
        self.matcher = None
        self._pending_scan = None

    def leave_mapping(self, map_name: str = "", map_to_odom: Pose2 | None = None) -> str:
        """Take ``map`` and ``map -> odom`` back: load ``map_name`` (default: the map of
        before) with the robot's odometry frame at ``map_to_odom`` in it when given.
        Refused (`MappingRefused` NOT_FOUND, still mapping) for an unknown map."""
        name = self.map_after_mapping(map_name)
        was = self.mapping
        self.mapping = False
        self.localizer.set_external(False)
        self._start_at = map_to_odom
        try:
            self.maps.switch(name)
        except (MapError, ValueError) as exc:
            self._start_at = None
            if was:  # the map would not load: the SLAM node's map stays in use
                self.mapping = True
                self.localizer.set_external(True)
            raise MappingRefused(ResultCode.INVALID, str(exc)) from exc
        return name

    def map_after_mapping(self, map_name: str) -> str:
        """The map `leave_mapping` would load (`MappingRefused` NOT_FOUND if not stored)."""
        name = map_name or self.maps.current
        try:
            return self.maps.store.require(name)
        except (MapError, ValueError) as exc:
            raise MappingRefused(ResultCode.NOT_FOUND, str(exc)) from exc

    def on_slam_map(self, grid: GridMap) -> None:
        """A new grid from the SLAM node (it grows; origin and size change): the costmaps
        are rebuilt on it; the planner's next snapshot (at most `replan_period` away) uses
        it."""
        if self.mapping:
            self.costmaps.set_map(grid)

    def on_slam_map_to_odom(self, map_to_odom: Pose2) -> None:
        if self.mapping:
            self.localizer.follow(map_to_odom)

    def _on_keepout(self, name: str) -> None:
        if name == self.maps.current:
            self.costmaps.set_keepout(self.maps.store.nav_data(name))

    # ------------------------------------------------------------------ sensors

    def on_odom(self, stamp_ns: int, pose: Pose2, v: float, w: float) -> None:
        self.localizer.on_odom(stamp_ns, pose)
        self.speed = (v, w)
        if self._pending_scan is not None:
            self._run_match()

    def on_ground_truth(self, stamp_ns: int, pose: Pose2) -> None:
        self.localizer.on_ground_truth(stamp_ns, pose)

    def on_scan(self, scan: Any, now: float) -> None:
        """Keep the scan's points (in base_link) for collision checks and, when due, update
        the global costmap's obstacle layer."""
        mount = self.scan_mounts.get(scan.header.frame_id, Pose2())
        ranges = np.asarray(scan.ranges, dtype=np.float64)
        n = len(ranges)
        if n == 0 or not (math.isfinite(scan.angle_min) and math.isfinite(scan.angle_increment)):
            return
        angles = scan.angle_min + scan.angle_increment * np.arange(n)
        # a robot at rest gets the same ranges at 10 Hz: its points (in base_link) are those
        # it has already
        key = (scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max, mount)
        if key != self._scan_key or not np.array_equal(ranges, self._scan_ranges):
            ok = np.isfinite(ranges) & (ranges >= scan.range_min) \
                & (ranges <= scan.range_max) & (ranges <= self.config.scan_max_points_range)
            r, a = ranges[ok], angles[ok] + mount.theta
            self.obstacles = np.column_stack([mount.x + r * np.cos(a), mount.y + r * np.sin(a)])
            self._scan_key, self._scan_ranges = key, ranges
        if self.localizer.mode == "scan_match" and not self.mapping:
            self._match(scan, ranges, angles, mount, now)
        pose = self.localizer.pose()
        if pose is not None:
            self.costmaps.update_from_scan(scan, pose * mount, now)

    def _match(self, scan: Any, ranges: np.ndarray, angles: np.ndarray, mount: Pose2,
               now: float) -> None:
        """Queue this scan for matching (at most ``scan_match_rate`` a second); it is
        matched once the odometry of its stamp is in (`_run_match`)."""
        rate = self.config.scan_match_rate
        if self.matcher is None or rate <= 0 or (0 <= now - self._last_match < 1.0 / rate):
            return
        self._last_match = now
        ok = np.isfinite(ranges) & (ranges >= scan.range_min) & (ranges <= scan.range_max)
        r, a = ranges[ok], angles[ok] + mount.theta
        pts = np.column_stack([mount.x + r * np.cos(a), mount.y + r * np.sin(a)])
        self._pending_scan = (scan.header.stamp.nanoseconds, pts)
        self._run_match()

    def _run_match(self) -> None:
        pending, matcher = self._pending_scan, self.matcher
        if pending is None or matcher is None or not self.localizer.covers(pending[0]):
            return
        self._pending_scan = None
        stamp, pts = pending
        guess = self.localizer.pose_at(stamp)
        if guess is None:
            return
        wide = self.localizer.relocalize
        found, score = matcher.match(pts, guess, wide=wide)
        if wide:  # then the tracking window, from where the wide search put it
            found, score = matcher.match(pts, found)
        self.match_score = score  # the localisation's quality (nav's diagnostics)
        if score >= matcher.p.min_score:
            self.localizer.correct(stamp, found, 1.0 if wide else self.config.scan_match_gain)

    def on_battery(self, percentage: float, charging: bool) -> None:
        if math.isfinite(percentage):
            self.battery = percentage
        self._battery_charging = charging

    def on_chassis(self, docked: bool, charging: bool) -> None:
        self.docked = docked
        self._chassis_charging = charging

    @property
    def charging(self) -> bool:
        """Charging, as either the battery or the chassis reports it."""
        return self._battery_charging or self._chassis_charging

    # ------------------------------------------------------------------ behaviours

    def make_nav(self, goal: Pose2, codes: Codes = Codes()) -> Navigate:
        return Navigate([goal], self, self.config.nav, self.config.controller, codes,
                        gate=self.traffic)

    def sense(self, now: float) -> Sense:
        dt = 0.0 if self._last_tick is None else max(0.0, now - self._last_tick)
        if dt > 0.5:
            dt = 0.0  # a pause (or a clock jump): no acceleration credit
        return Sense(now=now, dt=dt, pose=self.localizer.pose(), speed=self.speed,
                     obstacles=self.obstacles, battery=self.battery, charging=self.charging,
                     docked=self.docked)

    def tick(self, now: float) -> tuple[float, float] | None:
        """One control step at ``now`` (seconds, node clock): the command, or None."""
        s = self.sense(now)
        self._last_tick = now
        return self.motion.tick(s)

    def start(self, behavior: Behavior) -> None:
        self.motion.start(behavior)

    def close(self) -> None:
        self.motion.halt(reason="navigation is shutting down")
        self.worker.close()
