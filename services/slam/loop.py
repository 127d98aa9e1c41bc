"""LoopCloser: finds where a new node sees a place the graph passed long ago and measures the
edge (Karto's FindPossibleLoopClosure / TryCloseLoop).

Candidates are older nodes within ``loop_search_maximum_distance`` of the new one, not in the
running chain (more than ``loop_exclude_distance`` of travel back). The nearest one's chain
of ``loop_match_minimum_chain_size`` consecutive nodes makes a local map; the new scan is
matched against it over the wide loop window. The match is accepted only if the coarse
response passes ``loop_match_minimum_response_coarse``, the peak is not spread (its largest
principal variance under ``loop_match_maximum_variance_coarse``: a featureless corridor
matches equally well all along itself), and the fine response passes
``loop_match_minimum_response_fine``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .graph import Node, PoseGraph
from .matcher import CorrelationGrid, MatchResult, Window, match
from .params import SlamParameters
from .scan import points_in

__all__ = ["LoopCandidate", "LoopCloser", "thin"]


@dataclass(frozen=True)
class LoopCandidate:
    """A measured closure: node ``j`` (the new one) in the map of ``chain``, with ``result``
    its match; ``accepted`` false with ``reason`` when a check failed."""

    j: int
    chain: tuple[int, ...]
    result: MatchResult
    accepted: bool
    reason: str = ""


def thin(pts: np.ndarray, n: int) -> np.ndarray:
    if len(pts) > n:
        pts = pts[np.linspace(0, len(pts) - 1, n).astype(int)]
    return pts


class LoopCloser:
    def __init__(self, params: SlamParameters) -> None:
        p = params
        self.p = p
        half = p.loop_search_space_dimension / 2
        self.window = Window(xy=half, xy_step=4 * p.resolution,
                             theta=p.loop_search_angle_offset,
                             theta_step=p.coarse_angle_resolution,
                             fine_xy=p.resolution / 2, fine_theta=p.fine_search_angle_offset,
                             pool=4, candidates=4)

    def candidates(self, graph: PoseGraph, node: Node) -> list[int]:
        """Older nodes near ``node``, out of its running chain, nearest first."""
        p = self.p
        old = [n for n in graph.nodes[:node.index]
               if node.travelled - n.travelled > p.loop_exclude_distance]
        if not old:
            return []
        xy = np.array([(n.pose.x, n.pose.y) for n in old])
        d = np.hypot(xy[:, 0] - node.pose.x, xy[:, 1] - node.pose.y)
        near = np.flatnonzero(d <= p.loop_search_maximum_distance)
        return [old[k].index for k in near[np.argsort(d[near])]]

    def chain_around(self, graph: PoseGraph, k: int, newest: int) -> tuple[int, ...]:
        """``loop_match_minimum_chain_size`` consecutive nodes centred on ``k``, all out of
        the running chain of node ``newest``."""
        size = self.p.loop_match_minimum_chain_size
        limit = graph.nodes[newest].travelled - self.p.loop_exclude_distance
        lo = max(0, k - size // 2)
        hi = lo + size
        while hi > lo + 1 and graph.nodes[min(hi, len(graph.nodes)) - 1].travelled > limit:
            hi -= 1
        lo = max(0, hi - size)
        return tuple(range(lo, hi))

    def try_close(self, graph: PoseGraph, node: Node) -> LoopCandidate | None:
        """Match ``node`` against the nearest old chain; None if there is none to try."""
        near = self.candidates(graph, node)
        if not near:
            return None
        chain = self.chain_around(graph, near[0], node.index)
        if len(chain) < self.p.loop_match_minimum_chain_size:
            return None
        return self.measure(graph, node, chain)

    def measure(self, graph: PoseGraph, node: Node, chain: tuple[int, ...]) -> LoopCandidate:
        p = self.p
        ref = np.vstack([graph.nodes[i].world_points() for i in chain])
        pts = thin(node.scan.points, p.match_points)
        margin = p.loop_search_space_dimension / 2 + 1.0
        world = points_in(node.pose, pts)
        lo = np.minimum(world.min(axis=0), ref.min(axis=0))
        hi = np.maximum(world.max(axis=0), ref.max(axis=0))
        cg = CorrelationGrid(ref, p.resolution, p.correlation_search_space_smear_deviation,
                             margin, (lo[0], lo[1], hi[0], hi[1]))
        coarse = match(cg, pts, node.pose, self.window)
        j = node.index
        if coarse.response < p.loop_match_minimum_response_fine:
            return LoopCandidate(j, chain, coarse, False,
                                 f"response {coarse.response:.2f} < "
                                 f"{p.loop_match_minimum_response_fine}")
        spread = self._spread(cg, pts, coarse)
        if spread > p.loop_match_maximum_variance_coarse:
            return LoopCandidate(j, chain, coarse, False,
                                 f"ambiguous: variance {spread:.3f} m² > "
                                 f"{p.loop_match_maximum_variance_coarse}")
        return LoopCandidate(j, chain, coarse, True)

    def _spread(self, cg: CorrelationGrid, pts: np.ndarray, best: MatchResult) -> float:
        """The position variance of the response peak over the whole loop window at the
        best heading: cells scoring within ``loop_match_minimum_response_coarse``'s margin
        (0.1) of the best, as Karto's coarse covariance."""
        half = self.p.loop_search_space_dimension / 2
        step = 2 * self.p.resolution
        d = np.arange(-round(half / step), round(half / step) + 1) * step
        gx, gy = np.meshgrid(best.pose.x + d, best.pose.y + d, indexing="ij")
        poses = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, best.pose.theta)])
        sc = cg.scores(pts, poses)
        near = sc >= max(sc.max() - 0.1, self.p.loop_match_minimum_response_coarse)
        if not near.any():
            return float("inf")
        w = sc[near]
        dxy = poses[near, :2] - (best.pose.x, best.pose.y)
        cov = (dxy.T * w) @ dxy / w.sum()
        return float(np.linalg.eigvalsh(cov)[-1])
