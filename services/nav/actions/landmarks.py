"""`LandmarkServices`: the ``get_landmarks`` and ``relocalize_landmarks`` services and what
each scan shows of reflectors (``landmarks/detections``), over `NavCore`.

Relocalising takes the last scan, detects its reflectors (`localization.reflectors`),
matches them to the current map's ``landmarks.yaml`` and fits the robot's pose
(`localization.landmarks.locate`), then sets ``map -> odom`` from it with the odometry of
the scan's stamp, so the robot may be moving. A refusal is an answer (``success`` false and
the reason), never an exception: the tasks service calls it after an elevator ride.
"""

from __future__ import annotations

import math
import threading

import numpy as np
from zenros.errors import MapError
from zenros.maps import Reflector, load_landmarks
from zenros.msgs.geometry_msgs import Point, Pose2D
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs.nav import (
    GetLandmarksRequest,
    GetLandmarksResponse,
    Landmark,
    LandmarkDetections,
    RelocalizeLandmarksRequest,
    RelocalizeLandmarksResponse,
)
from zenros.se2 import Pose2, angle_diff

from ..core import NavCore
from ..localization.landmarks import LandmarkError, LocateParams, locate
from ..localization.reflectors import Detections, detect

__all__ = ["MAX_SCAN_AGE", "LandmarkServices"]

MAX_SCAN_AGE = 1.0
"""Seconds (of odometry time) the last scan may be older than the odometry to be used."""


class LandmarkServices:
    """Keeps the last scan; answers the landmark services from it."""

    def __init__(self, core: NavCore, base_frame: str = "base_link") -> None:
        self.core = core
        self.base_frame = base_frame
        self._lock = threading.Lock()
        self._scan: LaserScan | None = None

    def on_scan(self, scan: LaserScan) -> None:
        with self._lock:
            self._scan = scan

    def _map_landmarks(self, map_name: str) -> tuple[str, list[Reflector]]:
        """The map's name and reflectors (`MapItemNotFoundError`, `MapError` if it has
        none stored or a bad file)."""
        name = self.core.maps.resolve(map_name)
        return name, load_landmarks(self.core.maps.store.folder(name))

    def handle_get_landmarks(self, req: GetLandmarksRequest) -> GetLandmarksResponse:
        """A map's reflectors (the current map's for an empty ``map_name``)."""
        name, marks = self._map_landmarks(req.map_name)
        return GetLandmarksResponse(map_name=name, landmarks=[
            Landmark(id=m.id, x=m.x, y=m.y, radius=m.radius) for m in marks])

    def detect(self, scan: LaserScan) -> Detections:
        """The reflectors ``scan`` shows, in ``base_link`` (`ValueError` for a bad scan)."""
        mount = self.core.scan_mounts.get(scan.header.frame_id.lstrip("/"), Pose2())
        return detect(np.asarray(scan.ranges), np.asarray(scan.intensities), scan.angle_min,
                      scan.angle_increment, scan.range_min, scan.range_max, mount)

    def detections(self, scan: LaserScan) -> LandmarkDetections:
        """``landmarks/detections`` for ``scan`` (empty for a scan that cannot be read)."""
        try:
            found = self.detect(scan)
        except ValueError:
            found = Detections(np.zeros((0, 2)), np.zeros(0, dtype=np.int64))
        return LandmarkDetections(
            header=Header(stamp=scan.header.stamp, frame_id=self.base_frame),
            points=[Point(x=float(x), y=float(y)) for x, y in found.xy.tolist()],
            returns=[int(n) for n in found.returns])

    def handle_relocalize(self, req: RelocalizeLandmarksRequest
                          ) -> RelocalizeLandmarksResponse:
        """Set the robot's pose from the reflectors of the last scan."""
        try:
            return self._relocalize(req)
        except (LandmarkError, MapError, ValueError) as exc:
            return RelocalizeLandmarksResponse(success=False, message=str(exc),
                                               map_name=self.core.maps.current)

    def _relocalize(self, req: RelocalizeLandmarksRequest) -> RelocalizeLandmarksResponse:
        with self._lock:
            scan = self._scan
        if scan is None:
            raise ValueError("no scan has arrived yet")
        stamp = scan.header.stamp.nanoseconds
        loc = self.core.localizer
        age = (loc.odom_stamp_ns - stamp) / 1e9
        if not loc.odom_stamp_ns:
            raise ValueError("no odometry has arrived yet")
        if age > MAX_SCAN_AGE:
            raise ValueError(f"the last scan is {age:.1f} s older than the odometry "
                             f"(limit {MAX_SCAN_AGE:g} s): is the laser publishing?")
        name, marks = self._map_landmarks("")
        found = self.detect(scan)
        rough = loc.pose_at(stamp) if req.use_estimate else None
        params = LocateParams(min_matches=max(2, req.min_matches))
        fix = locate(found.xy, np.array([(m.x, m.y) for m in marks]).reshape(-1, 2), rough,
                     params)
        if not loc.set_pose_at(stamp, fix.pose):
            raise ValueError("map -> odom is another node's now (mapping mode)")
        p = fix.pose
        shift, turn = (0.0, 0.0) if rough is None else (
            math.hypot(p.x - rough.x, p.y - rough.y), abs(angle_diff(p.theta, rough.theta)))
        return RelocalizeLandmarksResponse(
            success=True, message=f"{len(fix.matches)} of {len(found)} reflectors matched",
            map_name=name, pose=Pose2D(x=p.x, y=p.y, theta=p.theta), detected=len(found),
            matched=len(fix.matches), ids=[marks[j].id for _, j in fix.matches],
            rms_error=fix.rms, shift=shift, turn=turn)
