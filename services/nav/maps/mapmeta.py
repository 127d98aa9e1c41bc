"""MapRecord: what a map's folder says about the map besides its grid (``record.yml``).

Its ``type`` (``floor`` or ``elevator``) and ``levels`` (the floors it serves, the robot
API's map objects), the sensor it was built with (``slam_type``), and, for a map the robot
built itself (``built_by_slam``), where its odometry frame was in it when it was saved
(``map_to_odom``): nav localises on such a map by scan matching from there, since the
simulator's ground truth is in the world's frame, not the built map's. A folder without the
file is an imported map: ``floor``, no levels, ``lidar``, not built.
"""

from __future__ import annotations

import math
from pathlib import Path

import msgspec
import msgspec.yaml
from zenros.errors import MapError
from zenros.msgs.geometry_msgs import Pose2D

__all__ = ["MAP_TYPES", "RECORD_FILE", "SLAM_TYPES", "MapRecord", "check_record",
           "read_record", "write_record"]

RECORD_FILE = "record.yml"  # .yml: never a map's own ``<name>.yaml``
MAP_TYPES = ("floor", "elevator")
SLAM_TYPES = ("lidar", "camera")


class MapRecord(msgspec.Struct, kw_only=True, omit_defaults=True):
    type: str = "floor"
    levels: list[int] = msgspec.field(default_factory=list)
    slam_type: str = "lidar"
    built_by_slam: bool = False
    map_to_odom: Pose2D | None = None


def check_record(rec: MapRecord) -> MapRecord:
    """``rec`` if its values are valid, else ValueError naming the field."""
    if rec.type not in MAP_TYPES:
        raise ValueError(f"type must be one of {', '.join(MAP_TYPES)}, got {rec.type!r}")
    if rec.slam_type not in SLAM_TYPES:
        raise ValueError(f"slam_type must be one of {', '.join(SLAM_TYPES)}, "
                         f"got {rec.slam_type!r}")
    if any(not isinstance(v, int) or isinstance(v, bool) for v in rec.levels):
        raise ValueError(f"levels must be integers, got {rec.levels!r}")
    p = rec.map_to_odom
    if p is not None and not all(math.isfinite(v) for v in (p.x, p.y, p.theta)):
        raise ValueError(f"map_to_odom must be finite, got ({p.x}, {p.y}, {p.theta})")
    return rec


def read_record(folder: Path) -> MapRecord:
    """The record in ``folder`` (defaults when there is none).

    Raises:
        MapError: the file is unreadable or malformed (names the file and the field).
    """
    path = folder / RECORD_FILE
    if not path.is_file():
        return MapRecord()
    try:
        return check_record(msgspec.yaml.decode(path.read_bytes(), type=MapRecord))
    except (OSError, msgspec.ValidationError, msgspec.DecodeError, ValueError) as exc:
        raise MapError(f"{path}: {exc}") from exc


def write_record(path: Path, rec: MapRecord) -> None:
    path.write_bytes(msgspec.yaml.encode(check_record(rec)))
