"""PoseGraph: the mapper's nodes (a scan and the base pose it was taken at) and edges (a
measured relative pose with its information), as Karto keeps them."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from zenros.se2 import Pose2

from .scan import RangeScan, points_in

__all__ = ["Edge", "Node", "PoseGraph", "relative"]


@dataclass
class Node:
    """A scan that became a graph node: ``pose`` (corrected, in map), ``odom`` (where the
    odometry had it), ``stamp`` (seconds)."""

    index: int
    pose: Pose2
    odom: Pose2
    stamp: float
    scan: RangeScan
    travelled: float = 0.0
    """Metres the base had driven since the first node, by the graph."""
    _world: tuple[Pose2, np.ndarray] | None = field(default=None, repr=False, compare=False)

    def world_points(self) -> np.ndarray:
        """The scan's returns in the map, at the node's current pose (cached per pose)."""
        if self._world is None or self._world[0] != self.pose:
            self._world = (self.pose, points_in(self.pose, self.scan.points))
        return self._world[1]


@dataclass(frozen=True)
class Edge:
    """``j`` seen from ``i`` is ``z``; ``information`` the inverse covariance (3x3);
    ``kind``: ``odom`` (sequential) or ``loop``."""

    i: int
    j: int
    z: Pose2
    information: np.ndarray
    kind: str = "odom"


def relative(a: Pose2, b: Pose2) -> Pose2:
    """``b`` in ``a``'s frame."""
    return a.inverse() * b


@dataclass
class PoseGraph:
    nodes: list[Node] = field(default_factory=list)
    edges: list[Edge] = field(default_factory=list)

    def add_node(self, pose: Pose2, odom: Pose2, stamp: float, scan: RangeScan) -> Node:
        travelled = 0.0
        if self.nodes:
            last = self.nodes[-1]
            travelled = last.travelled + last.pose.distance(pose)
        node = Node(len(self.nodes), pose, odom, stamp, scan, travelled)
        self.nodes.append(node)
        return node

    def add_edge(self, i: int, j: int, z: Pose2, covariance: np.ndarray,
                 kind: str = "odom") -> Edge:
        cov = np.asarray(covariance, dtype=np.float64)
        edge = Edge(i, j, z, np.linalg.inv(cov), kind)
        self.edges.append(edge)
        return edge

    @property
    def loop_closures(self) -> int:
        return sum(1 for e in self.edges if e.kind == "loop")

    def poses(self) -> np.ndarray:
        return np.array([n.pose for n in self.nodes], dtype=np.float64).reshape(-1, 3)

    def set_poses(self, poses: np.ndarray) -> None:
        travelled = 0.0
        for k, (node, p) in enumerate(zip(self.nodes, poses, strict=True)):
            node.pose = Pose2(float(p[0]), float(p[1]), float(p[2]))
            if k:
                travelled += self.nodes[k - 1].pose.distance(node.pose)
            node.travelled = travelled
