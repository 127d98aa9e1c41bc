"""Mapper: occupancy-grid SLAM from scans and odometry, the way Karto/slam_toolbox does it.

Each scan is placed at ``map_to_odom ∘ odom``. Once the base has moved
``minimum_travel_distance`` or turned ``minimum_travel_heading`` since the last node, the scan
is matched against the running buffer (the last ``scan_buffer_size`` nodes), becomes a node
with an edge from the previous one, and is ray-cast into the grid; ``map_to_odom`` takes the
correction. Then the loop closer looks for an old place near it; an accepted closure adds a
loop edge, the graph is optimised and the grid re-rasterised from the corrected poses.

The first scan's pose is its odometry pose: ``map_to_odom`` starts at identity, so the map
frame is the odometry frame (the robot's pose when mapping started, for a fresh odometry).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from zenros.se2 import Pose2, angle_diff

from .graph import Node, PoseGraph, relative
from .grid import LogOddsGrid
from .loop import LoopCandidate, LoopCloser, thin
from .matcher import CorrelationGrid, MatchResult, Window, match
from .optimizer import optimize
from .params import SlamParameters
from .scan import RangeScan, points_in

__all__ = ["Mapper", "Prior", "ScanOutcome"]

_MIN_SEQ_SIGMA = (0.02, 0.01)  # m, rad: a match is never trusted more than this
_ODOM_ONLY_SIGMA = (0.1, 0.05)


@dataclass(frozen=True)
class ScanOutcome:
    """What one scan did: ``pose`` of the base in map; ``node`` its index if it became one;
    ``closure`` the loop closure it tried (accepted or not); ``rebuilt``: a closure moved
    the nodes (the grid is re-rasterised from them when next read)."""

    pose: Pose2
    node: int | None = None
    response: float = 0.0
    closure: LoopCandidate | None = None
    rebuilt: bool = False


def _fuse(prev: Pose2, step: Pose2, step_cov: np.ndarray, matched: Pose2,
          match_cov: np.ndarray) -> tuple[Pose2, np.ndarray]:
    """The covariance-weighted mean of the odometry's and the match's relative step from
    ``prev`` (both in ``prev``'s frame), and its covariance."""
    z = relative(prev, matched)
    c, s = math.cos(prev.theta), math.sin(prev.theta)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    # the match's covariance is in the map frame: bring it into prev's
    mc = rot.T @ match_cov @ rot
    a, b = np.linalg.inv(step_cov), np.linalg.inv(mc)
    cov = np.linalg.inv(a + b)
    za = np.array(step)
    zb = np.array(z)
    zb[2] = za[2] + angle_diff(zb[2], za[2])
    mean = cov @ (a @ za + b @ zb)
    return prev * Pose2(float(mean[0]), float(mean[1]), float(mean[2])), cov


@dataclass(frozen=True)
class Prior:
    """A stored occupancy grid mapping goes on from: ``cells`` (map_server values, row 0 at
    ``origin``, yaw 0) and its occupied cells' centres as reference points."""

    cells: np.ndarray
    resolution: float
    origin: tuple[float, float]

    @cached_property
    def walls(self) -> np.ndarray:
        rows, cols = np.nonzero(self.cells >= 65)
        return np.column_stack([self.origin[0] + (cols + 0.5) * self.resolution,
                                self.origin[1] + (rows + 0.5) * self.resolution])

    def near(self, pts: np.ndarray, margin: float) -> np.ndarray:
        """The walls within the bounding box of ``pts`` grown by ``margin``."""
        walls = self.walls
        if not len(pts) or not len(walls):
            return walls[:0]
        lo, hi = pts.min(axis=0) - margin, pts.max(axis=0) + margin
        keep = np.all((walls >= lo) & (walls <= hi), axis=1)
        out: np.ndarray = walls[keep]
        return out


class Mapper:
    """Holds the graph, the grid and ``map_to_odom``; `add_scan` folds one scan in."""

    def __init__(self, params: SlamParameters = SlamParameters()) -> None:
        self.p = params
        p = params
        self.graph = PoseGraph()
        self._prior: Prior | None = None
        self._grid = self._new_grid()
        self._rasterised = 0  # nodes ray-cast into _grid
        self._stale = False
        self._closed_at = -math.inf
        self.loops = LoopCloser(p)
        self.map_to_odom = Pose2()
        self.pose = Pose2()
        self.scans = 0
        self.loop_closures = 0
        self.last_closure: LoopCandidate | None = None
        self._since_attempt = 0
        self._resume_at: Pose2 | None = None
        half = p.correlation_search_space_dimension / 2
        self.window = Window(
            xy=half, xy_step=p.resolution, theta=p.coarse_search_angle_offset,
            theta_step=p.coarse_angle_resolution, fine_xy=p.resolution / 4,
            fine_theta=p.fine_search_angle_offset,
            penalty=(p.distance_variance_penalty, p.angle_variance_penalty,
                     p.minimum_distance_penalty, p.minimum_angle_penalty))

    def _new_grid(self) -> LogOddsGrid:
        p = self.p
        grid = LogOddsGrid(p.resolution, p.hit_probability, p.miss_probability,
                           p.clamp_min, p.clamp_max)
        prior = self._prior
        if prior is not None and abs(prior.resolution - p.resolution) < 1e-9:
            grid.seed(prior.cells, prior.origin)
        return grid

    # ---------------------------------------------------------------- state

    @property
    def nodes(self) -> int:
        return len(self.graph.nodes)

    def pose_at(self, odom: Pose2) -> Pose2:
        return self.map_to_odom * odom

    @property
    def grid(self) -> LogOddsGrid:
        """The occupancy grid: the nodes added since it was last read are ray-cast into it
        now, or all of them again if a closure moved the nodes (slam_toolbox too builds its
        map at each map update, not at each scan)."""
        if self._stale:
            self.rebuild()
        nodes = self.graph.nodes
        for n in nodes[self._rasterised:]:
            self._grid.add_scan(n.pose, n.scan)
        self._rasterised = len(nodes)
        return self._grid

    def reset(self) -> None:
        self.graph = PoseGraph()
        self._prior = None
        self._grid = self._new_grid()
        self._rasterised = 0
        self._stale = False
        self._closed_at = -math.inf
        self.map_to_odom = Pose2()
        self.pose = Pose2()
        self.scans = self.loop_closures = self._since_attempt = 0
        self.last_closure = None
        self._resume_at = None

    def resume_on_grid(self, prior: Prior, at: Pose2) -> None:
        """Map on from a stored grid (a map not built here, with no pose graph): it is the
        map's frame and first layer, and the reference the first scans are matched against;
        the robot stands at ``at`` in it (relocalised with the loop window)."""
        self.reset()
        self._prior = prior
        self._grid = self._new_grid()
        self._resume_at = at
        self.pose = at

    def resume(self, graph: PoseGraph, at: Pose2 | None = None) -> None:
        """Map on from a saved ``graph``: the robot stands at ``at`` (default: the graph's
        last node). The next scan is placed there, relocalised against the old nodes near
        it (the wide loop window), and linked to the nearest of them."""
        self.reset()
        self.graph = graph
        self._stale = True
        self.loop_closures = graph.loop_closures
        if graph.nodes:
            self._closed_at = graph.nodes[-1].travelled
        self._resume_at = at if at is not None else (
            graph.nodes[-1].pose if graph.nodes else Pose2())
        self.pose = self._resume_at

    # ---------------------------------------------------------------- scans

    def moved_enough(self, odom: Pose2) -> bool:
        if not self.graph.nodes:
            return True
        last = self.graph.nodes[-1].odom
        d = relative(last, odom)
        return (math.hypot(d.x, d.y) >= self.p.minimum_travel_distance
                or abs(d.theta) >= self.p.minimum_travel_heading)

    def add_scan(self, stamp: float, odom: Pose2, scan: RangeScan) -> ScanOutcome:
        """Fold one scan taken with the odometry at ``odom`` in."""
        self.scans += 1
        if self._resume_at is not None:
            return self._first_resumed(stamp, odom, scan, self._resume_at)
        predicted = self.map_to_odom * odom
        if not self.moved_enough(odom):
            self.pose = predicted
            return ScanOutcome(predicted)
        graph = self.graph
        if not graph.nodes:
            node = graph.add_node(predicted, odom, stamp, scan)
            self.pose = predicted
            return ScanOutcome(predicted, node.index, 1.0)
        prev = graph.nodes[-1]
        result = self._match_sequential(predicted, scan)
        step = relative(prev.odom, odom)
        odom_cov = self._odom_covariance(step)
        if result.response >= self.p.link_match_minimum_response_fine:
            match_cov = result.covariance.copy()
            sx, st = _MIN_SEQ_SIGMA
            match_cov[0, 0] = max(match_cov[0, 0], sx * sx)
            match_cov[1, 1] = max(match_cov[1, 1], sx * sx)
            match_cov[2, 2] = max(match_cov[2, 2], st * st)
            pose, cov = _fuse(prev.pose, step, odom_cov, result.pose, match_cov)
        else:
            pose, cov = predicted, odom_cov
        node = graph.add_node(pose, odom, stamp, scan)
        graph.add_edge(prev.index, node.index, relative(prev.pose, pose), cov)
        self.map_to_odom = pose * odom.inverse()
        self.pose = pose
        closure = self._try_loop(node)
        rebuilt = False
        if closure is not None and closure.accepted:
            self._close(closure)
            rebuilt = True
        return ScanOutcome(self.pose, node.index, result.response, closure, rebuilt)

    def _odom_covariance(self, step: Pose2) -> np.ndarray:
        """The covariance of an odometry step (in the earlier node's frame)."""
        p = self.p
        dist = math.hypot(step.x, step.y)
        sxy = p.odom_translation_sigma * dist + 0.002
        sth = p.odom_rotation_sigma * abs(step.theta) + p.odom_drift_sigma * dist + 0.001
        return np.diag([sxy * sxy, sxy * sxy, sth * sth])

    def _match_sequential(self, guess: Pose2, scan: RangeScan) -> MatchResult:
        p = self.p
        buffer: list[Node] = []
        newest = self.graph.nodes[-1]
        for n in reversed(self.graph.nodes):
            if len(buffer) >= p.scan_buffer_size:
                break
            if n.pose.distance(newest.pose) > p.scan_buffer_maximum_scan_distance:
                break
            buffer.append(n)
        ref = np.vstack([n.world_points() for n in buffer])
        pts = thin(scan.points, p.match_points)
        if self._prior is not None:  # the stored map's walls are part of the reference
            ref = np.vstack([ref, self._prior.near(points_in(guess, pts), 1.0)])
        if len(ref) < 10 or len(pts) < 10:
            return MatchResult(guess, 0.0, np.diag([500.0, 500.0, 500.0]))
        world = points_in(guess, pts)
        margin = p.correlation_search_space_dimension / 2 + 0.5
        lo, hi = world.min(axis=0), world.max(axis=0)
        # only the reference near where the scan can land matters
        keep = np.all((ref >= lo - margin) & (ref <= hi + margin), axis=1)
        cg = CorrelationGrid(ref[keep], p.resolution, p.correlation_search_space_smear_deviation,
                             margin, (lo[0], lo[1], hi[0], hi[1]))
        return match(cg, pts, guess, self.window, thin(scan.points, 2 * p.match_points))

    def _first_resumed(self, stamp: float, odom: Pose2, scan: RangeScan,
                       at: Pose2) -> ScanOutcome:
        self._resume_at = None
        graph = self.graph
        if not graph.nodes:
            pose, response = at, 1.0
            if self._prior is not None:
                found = self._relocalise_on_prior(scan, at)
                pose, response = found.pose, found.response
            self.map_to_odom = pose * odom.inverse()
            node = graph.add_node(pose, odom, stamp, scan)
            self.pose = pose
            return ScanOutcome(pose, node.index, response)
        xy = np.array([(n.pose.x, n.pose.y) for n in graph.nodes])
        d = np.hypot(xy[:, 0] - at.x, xy[:, 1] - at.y)
        nearest = int(np.argmin(d))
        lo = max(0, nearest - self.p.loop_match_minimum_chain_size // 2)
        chain = tuple(range(lo, min(len(graph.nodes),
                                    lo + self.p.loop_match_minimum_chain_size)))
        probe = graph.add_node(at, odom, stamp, scan)
        loop = self.loops.measure(graph, probe, chain)
        pose = loop.result.pose if loop.accepted else at
        probe.pose = pose
        anchor = graph.nodes[nearest]
        cov = loop.result.covariance if loop.accepted else np.diag([0.25, 0.25, 0.1])
        graph.add_edge(anchor.index, probe.index, relative(anchor.pose, pose), cov, "loop")
        self.map_to_odom = pose * odom.inverse()
        self.pose = pose
        self._stale = True
        return ScanOutcome(pose, probe.index, loop.result.response, loop)

    def _relocalise_on_prior(self, scan: RangeScan, at: Pose2) -> MatchResult:
        """``scan`` matched against the prior's walls round ``at`` with the loop window; ``at``
        itself if the match is too weak to trust."""
        assert self._prior is not None
        p = self.p
        pts = thin(scan.points, p.match_points)
        ref = self._prior.near(points_in(at, pts), p.loop_search_space_dimension / 2 + 1.0)
        if len(ref) < 10 or len(pts) < 10:
            return MatchResult(at, 0.0, np.diag([500.0, 500.0, 500.0]))
        margin = p.loop_search_space_dimension / 2 + 1.0
        lo, hi = ref.min(axis=0), ref.max(axis=0)
        cg = CorrelationGrid(ref, p.resolution, p.correlation_search_space_smear_deviation,
                             margin, (lo[0], lo[1], hi[0], hi[1]))
        found = match(cg, pts, at, self.loops.window, thin(scan.points, 2 * p.match_points))
        if found.response < p.loop_match_minimum_response_fine:
            return MatchResult(at, found.response, found.covariance)
        return found

    # ---------------------------------------------------------------- loops

    def _try_loop(self, node: Node) -> LoopCandidate | None:
        if not self.p.do_loop_closing:
            return None
        self._since_attempt += 1
        if self._since_attempt < self.p.loop_attempt_every:
            return None
        # one closure per stretch of loop_search_maximum_distance travelled
        if node.travelled - self._closed_at < self.p.loop_search_maximum_distance:
            return None
        candidate = self.loops.try_close(self.graph, node)
        if candidate is not None:
            self._since_attempt = 0
            self.last_closure = candidate
        return candidate

    def _close(self, closure: LoopCandidate) -> None:
        graph = self.graph
        node = graph.nodes[closure.j]
        # the edge from the chain's middle node to the new one, as matched
        anchor = graph.nodes[closure.chain[len(closure.chain) // 2]]
        cov = closure.result.covariance.copy()
        sx, st = _MIN_SEQ_SIGMA
        cov[0, 0], cov[1, 1] = max(cov[0, 0], sx * sx), max(cov[1, 1], sx * sx)
        cov[2, 2] = max(cov[2, 2], st * st)
        graph.add_edge(anchor.index, node.index, relative(anchor.pose, closure.result.pose),
                       cov, "loop")
        self.loop_closures += 1
        self.optimize()
        self._closed_at = node.travelled

    def optimize(self) -> None:
        graph = self.graph
        res = optimize(graph.poses(), graph.edges, self.p.optimizer_iterations,
                       self.p.loop_huber_scale)
        graph.set_poses(res.poses)
        last = graph.nodes[-1]
        self.map_to_odom = last.pose * last.odom.inverse()
        self.pose = last.pose
        self._stale = True

    def rebuild(self) -> None:
        """Re-rasterise the grid from every node at its corrected pose (on the next read)."""
        self._grid = self._new_grid()
        self._rasterised = 0
        self._stale = False

    def track(self) -> list[tuple[float, Pose2]]:
        return [(n.stamp, n.pose) for n in self.graph.nodes]
