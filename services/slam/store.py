"""The pose graph on disk: ``$ZENROS_HOME/slam/<name>.posegraph``, MessagePack of typed
Structs (msgspec; never pickle): every node (pose, odometry, stamp and its scan's ranges),
every edge (measurement, information, kind), and ``map -> odom`` when it was written."""

from __future__ import annotations

import os
import re
from pathlib import Path

import msgspec
import numpy as np
from zenros.se2 import Pose2

from .graph import PoseGraph
from .scan import RangeScan

__all__ = ["FORMAT", "GraphFile", "check_name", "load_graph", "save_graph"]

FORMAT = "zenros-slam-posegraph/1"
_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.\-]{0,63}$")


def check_name(name: str) -> str:
    """``name`` if it is a safe map name (nav's rule: 1-64 letters, digits, ``_ . -``, not
    starting with ``.`` or ``-``); raises ValueError naming the rule otherwise."""
    if not isinstance(name, str) or not _NAME.match(name) or name in (".", ".."):
        raise ValueError(f"invalid map name {name!r}: use 1-64 letters, digits, '_', '.' or "
                         "'-', not starting with '.' or '-'")
    return name


class ScanRecord(msgspec.Struct, array_like=True):
    ranges: bytes
    angle_min: float
    angle_increment: float
    mount: tuple[float, float, float]
    range_min: float
    max_range: float
    clear_range: float


class NodeRecord(msgspec.Struct, array_like=True):
    pose: tuple[float, float, float]
    odom: tuple[float, float, float]
    stamp: float
    scan: ScanRecord


class EdgeRecord(msgspec.Struct, array_like=True):
    i: int
    j: int
    z: tuple[float, float, float]
    information: list[float]
    kind: str


class GraphFile(msgspec.Struct, kw_only=True):
    format: str = FORMAT
    resolution: float = 0.05
    map_to_odom: tuple[float, float, float] = (0.0, 0.0, 0.0)
    nodes: list[NodeRecord] = msgspec.field(default_factory=list)
    edges: list[EdgeRecord] = msgspec.field(default_factory=list)


def _xyt(pose: Pose2) -> tuple[float, float, float]:
    return (pose.x, pose.y, pose.theta)


def _scan_record(scan: RangeScan) -> ScanRecord:
    a = scan.angles
    inc = float(a[1] - a[0]) if len(a) > 1 else 0.0
    return ScanRecord(np.asarray(scan.ranges, dtype="<f4").tobytes(), float(a[0]), inc,
                      _xyt(scan.mount), scan.range_min, scan.max_range, scan.clear_range)


def save_graph(path: Path, graph: PoseGraph, map_to_odom: Pose2, resolution: float) -> None:
    """Write ``graph`` to ``path`` (atomically: a temporary file renamed over it)."""
    doc = GraphFile(
        resolution=resolution, map_to_odom=_xyt(map_to_odom),
        nodes=[NodeRecord(_xyt(n.pose), _xyt(n.odom), n.stamp, _scan_record(n.scan))
               for n in graph.nodes],
        edges=[EdgeRecord(e.i, e.j, _xyt(e.z), [float(v) for v in e.information.ravel()],
                          e.kind) for e in graph.edges])
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(msgspec.msgpack.encode(doc))
    os.replace(tmp, path)


def load_graph(path: Path) -> tuple[PoseGraph, Pose2, float]:
    """The graph, ``map -> odom`` and resolution stored at ``path``.

    Raises:
        FileNotFoundError: no such file.
        ValueError: the file is not a pose graph this version reads.
    """
    try:
        doc = msgspec.msgpack.decode(path.read_bytes(), type=GraphFile)
    except msgspec.DecodeError as exc:
        raise ValueError(f"{path} is not a pose graph: {exc}") from exc
    if doc.format != FORMAT:
        raise ValueError(f"{path}: format {doc.format!r}, expected {FORMAT!r}")
    graph = PoseGraph()
    for rec in doc.nodes:
        s = rec.scan
        ranges = np.frombuffer(s.ranges, dtype="<f4").astype(np.float32)
        angles = s.angle_min + np.arange(len(ranges)) * s.angle_increment
        scan = RangeScan(ranges, angles, Pose2(*s.mount), s.range_min, s.max_range,
                         s.clear_range)
        graph.add_node(Pose2(*rec.pose), Pose2(*rec.odom), rec.stamp, scan)
    n = len(graph.nodes)
    for e in doc.edges:
        if not (0 <= e.i < n and 0 <= e.j < n) or len(e.information) != 9:
            raise ValueError(f"{path}: edge {e.i}->{e.j} does not fit the {n} nodes")
        info = np.array(e.information, dtype=np.float64).reshape(3, 3)
        graph.add_edge(e.i, e.j, Pose2(*e.z), np.linalg.inv(info), e.kind)
    return graph, Pose2(*doc.map_to_odom), doc.resolution
