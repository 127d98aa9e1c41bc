"""MappingSession: one mapping run's state between the node and the mapper, without Zenoh.

It keeps the odometry of the last seconds (to place each scan at its stamp), hands scans to
the `ScanWorker`, and guards the `Mapper` with a lock so the node's timers can read the map,
the track and ``map -> odom`` while the worker folds scans in.
"""

from __future__ import annotations

import bisect
import math
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from zenros.se2 import Pose2, wrap_angle

from .graph import PoseGraph, relative
from .mapper import Mapper, Prior, ScanOutcome
from .params import SlamParameters
from .scan import RangeScan
from .worker import ScanWorker

__all__ = ["MapSnapshot", "MappingSession", "OdomBuffer"]

_ODOM_KEEP = 5.0  # seconds of odometry kept
_ODOM_LATE = 0.25  # a scan this much newer than the last odometry uses the last one


class OdomBuffer:
    """Odometry poses by stamp (seconds), interpolated at a scan's stamp."""

    def __init__(self) -> None:
        self._t: deque[float] = deque()
        self._p: deque[Pose2] = deque()

    def add(self, t: float, pose: Pose2) -> None:
        if self._t and t < self._t[-1]:  # time went back (a restarted sim): start over
            self._t.clear()
            self._p.clear()
        self._t.append(t)
        self._p.append(pose)
        while self._t and self._t[0] < t - _ODOM_KEEP:
            self._t.popleft()
            self._p.popleft()

    def at(self, t: float) -> Pose2 | None:
        """The odometry at ``t``, or None if it is not known (none yet, too old or too new)."""
        if not self._t or t < self._t[0] or t > self._t[-1] + _ODOM_LATE:
            return None
        if t >= self._t[-1]:
            return self._p[-1]
        ts = list(self._t)
        k = bisect.bisect_left(ts, t)
        if ts[k] == t or k == 0:
            return self._p[k]
        t0, t1 = ts[k - 1], ts[k]
        a, b = self._p[k - 1], self._p[k]
        f = (t - t0) / (t1 - t0)
        return Pose2(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y),
                     wrap_angle(a.theta + f * wrap_angle(b.theta - a.theta)))


@dataclass(frozen=True)
class MapSnapshot:
    cells: np.ndarray
    resolution: float
    origin: tuple[float, float]
    area_m2: float


@dataclass(frozen=True)
class ScanItem:
    stamp: float
    scan: RangeScan
    odom: Pose2 | None
    """The odometry at ``stamp`` when the scan came (None: not known yet)."""


class MappingSession:
    """Folds scans into a `Mapper` on a worker thread; every read goes through ``lock``.
    With ``threaded=False`` (a deterministic replay) scans are folded in the caller.

    ``on_folded(outcome, stamp)`` is called on the worker after each scan.
    """

    def __init__(self, params: SlamParameters,
                 on_folded: Callable[[ScanOutcome, float], None] | None = None,
                 on_error: Callable[[BaseException], None] | None = None, *,
                 threaded: bool = True) -> None:
        self.p = params
        self.mapper = Mapper(params)
        self.lock = threading.Lock()
        self.odom = OdomBuffer()
        self.mount = Pose2(params.laser_x, params.laser_y, params.laser_yaw)
        self.paused = False
        self.active = False
        self.no_odom = 0
        self.last_stamp = 0.0
        self._latest = (0.0, Pose2())  # the newest scan's stamp and base pose in map
        self._latest_lock = threading.Lock()
        self.moved_only = 0
        self.node_cpu_ms: deque[float] = deque(maxlen=1000)
        self._last_node_odom: Pose2 | None = None
        self._on_folded = on_folded
        self.worker: ScanWorker[ScanItem] = ScanWorker(self._fold, params.scan_queue_size,
                                                           on_error=on_error,
                                                           threaded=threaded)

    # ---------------------------------------------------------------- control

    def begin(self, graph: PoseGraph | None = None, at: Pose2 | None = None,
              prior: Prior | None = None) -> None:
        """Start mapping: empty, on from ``graph``, or on from the stored grid ``prior``,
        with the robot at ``at``."""
        self.worker.clear()
        self.worker.wait_idle(5.0)
        with self.lock:
            if graph is not None:
                self.mapper.resume(graph, at)
            elif prior is not None:
                self.mapper.resume_on_grid(prior, at or Pose2())
            else:
                self.mapper.reset()
            self.no_odom = self.moved_only = 0
            self._last_node_odom = None
            self._latest = (0.0, self.mapper.pose)
            self.active = True
        self.worker.start()

    def end(self) -> None:
        self.active = False
        self.worker.clear()
        self.worker.wait_idle(5.0)

    def reset(self) -> None:
        self.worker.clear()
        self.worker.wait_idle(5.0)
        with self.lock:
            self.mapper.reset()
            self._last_node_odom = None

    def close(self) -> None:
        self.active = False
        self.worker.close()

    # ---------------------------------------------------------------- inputs

    def on_odom(self, t: float, pose: Pose2) -> None:
        self.odom.add(t, pose)

    def on_scan(self, t: float, ranges: np.ndarray | list[float], angle_min: float,
                angle_increment: float, range_min: float, range_max: float) -> bool:
        """Fold a scan in; False (with nothing done) while not mapping or paused.

        A scan taken before the base moved ``minimum_travel_distance`` or turned
        ``minimum_travel_heading`` since the last node only moves the pose by odometry
        (Karto's gating, decided on the odometry alone): that is done here at once. The
        others, which the mapper matches and adds to the graph, go to the worker in order.

        Raises:
            ValueError: a scan with no beams or non-finite angles.
        """
        if not self.active or self.paused:
            return False
        p = self.p
        scan = RangeScan.from_laser(ranges, angle_min, angle_increment, self.mount,
                                    range_min, range_max, p.max_laser_range, p.max_clear_range)
        odom = self.odom.at(t)
        last = self._last_node_odom
        if odom is not None and last is not None and not self._moved(last, odom):
            self.moved_only += 1
            pose = self.mapper.map_to_odom * odom  # one attribute read: no lock needed
            self._note(t, pose)
            if self._on_folded is not None:
                self._on_folded(ScanOutcome(pose), t)
            return True
        if odom is not None:
            self._last_node_odom = odom
        self.worker.submit(ScanItem(t, scan, odom))
        return True

    def _note(self, t: float, pose: Pose2) -> None:
        with self._latest_lock:
            if t >= self._latest[0]:
                self._latest = (t, pose)

    def _moved(self, last: Pose2, odom: Pose2) -> bool:
        d = relative(last, odom)
        return (math.hypot(d.x, d.y) >= self.p.minimum_travel_distance
                or abs(d.theta) >= self.p.minimum_travel_heading)

    def _fold(self, item: ScanItem) -> None:
        odom = item.odom if item.odom is not None else self.odom.at(item.stamp)
        if odom is None:
            self.no_odom += 1
            return
        with self.lock:
            if not self.active:
                return
            t0 = time.thread_time()
            out = self.mapper.add_scan(item.stamp, odom, item.scan)
            if out.node is not None:
                self.node_cpu_ms.append((time.thread_time() - t0) * 1e3)
            self.last_stamp = max(self.last_stamp, item.stamp)
        self._note(item.stamp, out.pose)
        if self._on_folded is not None:
            self._on_folded(out, item.stamp)

    # ---------------------------------------------------------------- reads

    @property
    def skipped(self) -> int:
        return self.worker.skipped

    def snapshot(self) -> MapSnapshot | None:
        """The occupancy grid now (re-rasterised if a closure moved the nodes), or None
        before the first node."""
        with self.lock:
            if not self.mapper.graph.nodes:
                return None
            grid = self.mapper.grid
            cells = grid.occupancy()
            res = grid.res
            origin = (grid.ox, grid.oy)
        area = float(np.count_nonzero(cells >= 0)) * res * res
        return MapSnapshot(cells, res, origin, area)

    def track(self) -> tuple[list[Pose2], list[float]]:
        with self.lock:
            nodes = self.mapper.graph.nodes
            return [n.pose for n in nodes], [n.stamp for n in nodes]

    def pose(self) -> tuple[Pose2, Pose2, float]:
        """(base pose in map, map -> odom, stamp of the newest scan folded in)."""
        with self._latest_lock:
            stamp, pose = self._latest
        return pose, self.mapper.map_to_odom, stamp

    def counts(self) -> tuple[int, int, int]:
        """(scans folded, nodes, loop closures)."""
        with self.lock:
            m = self.mapper
            return m.scans + self.moved_only, m.nodes, m.loop_closures

    def has_map(self) -> bool:
        with self.lock:
            return bool(self.mapper.graph.nodes)

