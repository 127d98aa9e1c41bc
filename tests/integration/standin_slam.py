"""Stand-ins for the SLAM node in nav's and the explorer's tests (the contract's behaviour,
docs/mapping.md, without the real mapper): a map "built" in a frame that is not the world's,
and a mapper that grows a grid from the scans at the simulator's true pose.

- `reframe(world, T)`: the world's grid as seen from frame B, where ``T`` is B's pose in the
  world (``world_T_B``): a built map's frame is the robot's pose when mapping started, so a
  goal in B is reached at ``T * goal`` in the world.
- `TruthMapper`: in mapping mode publishes ``map`` (latched, growing: origin and size change
  as it does) and ``map -> odom`` on ``/tf``, as the SLAM node does, from the truth.
- `reachable_free`: the free
  cells of a world the robot can reach from a point (worlds to explore: tests/worlds.py);
  `coverage`: the share of them a built map knows (the explorer's figure), after `align` put
  the built map in the world's frame.
"""

from __future__ import annotations

import math
import threading
import time

from pathlib import Path

import numpy as np
from scipy import ndimage
from zenros.maps import GridMap
from zenros.msgs.geometry_msgs import Transform, TransformStamped, Vector3
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.std_msgs import Header
from zenros.msgs.tf2_msgs import TFMessage
from zenros.node import Node
from zenros.qos import QOS_LATCHED, QOS_SENSOR
from zenros.se2 import Pose2
from zenros.tf import yaw_to_msg


def reframe(world: GridMap, T: Pose2, res: float | None = None) -> GridMap:
    """``world`` resampled (nearest cell) on a grid in frame B, B at ``T`` in the world."""
    res = res or world.resolution
    ox, oy, _ = world.origin
    w, h = world.width * world.resolution, world.height * world.resolution
    inv = T.inverse()
    corners = [inv * Pose2(ox + dx, oy + dy, 0.0) for dx in (0, w) for dy in (0, h)]
    x0, y0 = min(c.x for c in corners), min(c.y for c in corners)
    x1, y1 = max(c.x for c in corners), max(c.y for c in corners)
    nx, ny = math.ceil((x1 - x0) / res), math.ceil((y1 - y0) / res)
    bx = x0 + (np.arange(nx) + 0.5) * res
    by = y0 + (np.arange(ny) + 0.5) * res
    gx, gy = np.meshgrid(bx, by)
    c, s = math.cos(T.theta), math.sin(T.theta)
    wx, wy = T.x + c * gx - s * gy, T.y + s * gx + c * gy
    col = np.floor((wx - ox) / world.resolution).astype(int)
    row = np.floor((wy - oy) / world.resolution).astype(int)
    inside = (col >= 0) & (col < world.width) & (row >= 0) & (row < world.height)
    out = np.full((ny, nx), -1, dtype=np.int8)
    out[inside] = world.grid[row[inside], col[inside]]
    return GridMap(out, res, (x0, y0, 0.0))



def map_to_odom_tf(p: Pose2, stamp: object) -> TFMessage:
    return TFMessage(transforms=[TransformStamped(
        header=Header(stamp=stamp, frame_id="map"), child_frame_id="odom",
        transform=Transform(translation=Vector3(x=p.x, y=p.y), rotation=yaw_to_msg(p.theta)))])


class TruthMapper:
    """Builds a grid from ``scan`` at the true pose (world frame = map frame) on ``node``;
    `start` declares the latched ``map`` publisher (after nav handed it over), `stop` drops it.
    Hits mark, rays clear (counts, as Karto's grid); published every ``period`` seconds of
    wall time, cropped to the known cells plus a margin. With ``gated`` it behaves as Karto
    does at the start: a scan is folded in only after a move of 0.5 m or a turn of 0.5 rad,
    and a cell is free only once two scans crossed it, so a robot at rest has a map of the
    walls its first scan hit and nothing free."""

    def __init__(self, node: Node, bounds: GridMap, period: float = 1.0,
                 gated: bool = False) -> None:
        self.node = node
        self.res = bounds.resolution
        self.ox, self.oy = bounds.origin[0], bounds.origin[1]
        self.hits = np.zeros(bounds.grid.shape, dtype=np.int32)
        self.passes = np.zeros(bounds.grid.shape, dtype=np.int32)
        self.lock = threading.Lock()
        self.truth: Pose2 | None = None
        self.odom: dict[int, Pose2] = {}
        self.map_to_odom = Pose2()
        self.pub: object | None = None
        self.tf_pub = node.create_publisher(TFMessage, "/tf")
        self.published = 0
        self.scan_rate = 10.0
        self._last_scan = -math.inf
        self.gated = gated
        self._folded_at: Pose2 | None = None
        node.create_subscription(Odometry, "sim/ground_truth", self._on_truth, QOS_SENSOR)
        node.create_subscription(Odometry, "odom", self._on_odom, QOS_SENSOR)
        node.create_subscription(LaserScan, "scan", self._on_scan, QOS_SENSOR)
        node.create_timer(period, self._publish)
        node.create_timer(0.1, self._publish_tf)

    @staticmethod
    def _pose(msg: Odometry) -> Pose2:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        return Pose2(p.x, p.y, 2 * math.atan2(q.z, q.w))

    def _on_odom(self, msg: Odometry) -> None:
        with self.lock:
            self.odom[msg.header.stamp.nanoseconds] = self._pose(msg)
            if len(self.odom) > 200:
                self.odom.pop(next(iter(self.odom)))

    def _on_truth(self, msg: Odometry) -> None:
        pose = self._pose(msg)
        with self.lock:
            self.truth = pose
            odom = self.odom.get(msg.header.stamp.nanoseconds)
            if odom is not None:
                self.map_to_odom = pose * odom.inverse()

    def _on_scan(self, msg: LaserScan) -> None:
        now = time.monotonic()
        with self.lock:
            pose = self.truth
            # at most `scan_rate` scans a wall second: at 10x the laser sends 100, and folding
            # each in would hold up this session's other callbacks (the truth, odom)
            if pose is None or self.pub is None or now - self._last_scan < 1 / self.scan_rate:
                return
            last = self._folded_at
            if self.gated and last is not None and last.distance(pose) < 0.5 \
                    and abs(math.remainder(pose.theta - last.theta, 2 * math.pi)) < 0.5:
                return
            self._last_scan, self._folded_at = now, pose
        r = np.asarray(msg.ranges, dtype=np.float64)
        a = msg.angle_min + msg.angle_increment * np.arange(len(r)) + pose.theta
        hit = np.isfinite(r) & (r < msg.range_max)
        r = np.where(np.isfinite(r), np.minimum(r, msg.range_max), msg.range_max)
        steps = np.arange(0.0, 1.0, self.res / 2 / max(float(r.max()), self.res))
        xs = pose.x + np.outer(r * np.cos(a), steps)
        ys = pose.y + np.outer(r * np.sin(a), steps)
        h, w = self.hits.shape
        col = np.floor((xs - self.ox) / self.res).astype(int).ravel()
        row = np.floor((ys - self.oy) / self.res).astype(int).ravel()
        ok = (col >= 0) & (col < w) & (row >= 0) & (row < h)
        ex = np.floor((pose.x + r[hit] * np.cos(a[hit]) - self.ox) / self.res).astype(int)
        ey = np.floor((pose.y + r[hit] * np.sin(a[hit]) - self.oy) / self.res).astype(int)
        eok = (ex >= 0) & (ex < w) & (ey >= 0) & (ey < h)
        with self.lock:
            cells = np.unique(row[ok] * w + col[ok])
            self.passes.ravel()[cells] += 1
            self.hits[ey[eok], ex[eok]] += 3

    def grid(self) -> GridMap | None:
        with self.lock:
            occ = self.hits > self.passes
            seen = (self.passes >= (2 if self.gated else 1)) | occ
            rows, cols = np.nonzero(seen)
            if len(rows) == 0:
                return None
            r0, r1 = max(rows.min() - 5, 0), min(rows.max() + 6, seen.shape[0])
            c0, c1 = max(cols.min() - 5, 0), min(cols.max() + 6, seen.shape[1])
            g = np.where(seen, np.where(occ, 100, 0), -1).astype(np.int8)[r0:r1, c0:c1]
        return GridMap(np.ascontiguousarray(g), self.res,
                       (self.ox + c0 * self.res, self.oy + r0 * self.res, 0.0))

    def start(self) -> None:
        self.pub = self.node.create_publisher(OccupancyGrid, "map", QOS_LATCHED)

    def stop(self) -> None:
        pub, self.pub = self.pub, None
        if pub is not None:
            self.node.destroy(pub)

    def _publish(self) -> None:
        pub, g = self.pub, self.grid()
        if pub is not None and g is not None:
            pub.publish(g.to_msg("map", self.node.now()))  # type: ignore[attr-defined]
            self.published += 1

    def _publish_tf(self) -> None:
        if self.pub is not None:
            with self.lock:
                m = self.map_to_odom
            self.tf_pub.publish(map_to_odom_tf(m, self.node.now()))


def reachable_free(world: GridMap, start: tuple[float, float]) -> np.ndarray:
    free = (world.grid >= 0) & (world.grid <= 25)
    labels, _ = ndimage.label(free)
    r, c = world.world_to_cell(*start)
    return labels == labels[r, c]


def coverage(world: GridMap, built: GridMap, reach: np.ndarray,
             built_in_world: Pose2 | None = None) -> float:
    """Share of ``reach`` (world cells) known in ``built``, whose frame is at
    ``built_in_world`` in the world's (default: the same frame)."""
    rows, cols = np.nonzero(reach)
    xs = world.origin[0] + (cols + 0.5) * world.resolution
    ys = world.origin[1] + (rows + 0.5) * world.resolution
    if built_in_world is not None:
        t = built_in_world
        c, s = math.cos(t.theta), math.sin(t.theta)
        xs, ys = c * (xs - t.x) + s * (ys - t.y), -s * (xs - t.x) + c * (ys - t.y)
    br = np.floor((ys - built.origin[1]) / built.resolution).astype(int)
    bc = np.floor((xs - built.origin[0]) / built.resolution).astype(int)
    ok = (br >= 0) & (br < built.height) & (bc >= 0) & (bc < built.width)
    known = np.zeros(len(rows), dtype=bool)
    known[ok] = built.grid[br[ok], bc[ok]] >= 0
    return float(known.mean())


def align(world: GridMap, built: GridMap) -> Pose2:
    """Where ``built``'s frame sits in the world's: its occupied cells matched against the
    world's walls (nav's correlative matcher, wide window round the identity), as the
    accuracy measures put a built map in the truth frame first (specs/mapping.md, section
    9): a map built with noise is a little rotated and shifted."""
    from zenros.services.nav.localization.scanmatch import MatchParams, ScanMatcher

    rows, cols = np.nonzero(built.grid >= 65)
    pts = np.column_stack([built.origin[0] + (cols + 0.5) * built.resolution,
                           built.origin[1] + (rows + 0.5) * built.resolution])
    matcher = ScanMatcher(world, MatchParams(max_points=3000))
    found, _ = matcher.match(pts, Pose2(), wide=True)
    found, _ = matcher.match(pts, found)
    return found
