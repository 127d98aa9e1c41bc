"""MapNavData: a map's nav points, paths, virtual walls, forbidden areas and charge pose.

Stored as ``nav.yaml`` in the map's folder; the fields are the zenros_msgs/nav types, so
what a service returns is what the file holds. `check_*` functions refuse bad values
(non-finite numbers, duplicate point names, walls of one point) with a message naming the
offending item.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from pathlib import Path

import msgspec
import msgspec.yaml
from zenros.errors import MapError
from zenros.msgs.geometry_msgs import Point, Pose2D
from zenros.msgs.zenros_msgs.nav import ForbiddenArea, NavPoint, VirtualWall

__all__ = [
    "NAV_FILE",
    "MapNavData",
    "StoredPath",
    "check_area",
    "check_name",
    "check_nav_points",
    "check_points",
    "check_pose",
    "check_wall",
    "read_nav_data",
    "write_nav_data",
]

NAV_FILE = "nav.yaml"
_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.\-]{0,63}$")


class StoredPath(msgspec.Struct, kw_only=True, omit_defaults=True):
    """A path: its recorded points (``x y z``) and its indexed nav points."""

    points: list[Point] = msgspec.field(default_factory=list)
    nav_points: list[NavPoint] = msgspec.field(default_factory=list)


class MapNavData(msgspec.Struct, kw_only=True, omit_defaults=True):
    """Everything nav keeps about one map besides the grid itself."""

    paths: dict[str, StoredPath] = msgspec.field(default_factory=dict)
    virtual_walls: list[VirtualWall] = msgspec.field(default_factory=list)
    forbidden_areas: list[ForbiddenArea] = msgspec.field(default_factory=list)
    charge_pose: Pose2D | None = None


def check_name(kind: str, name: str) -> str:
    """``name`` if it is a safe map or path name (letters, digits, ``_ . -``; <= 64 chars)."""
    if not isinstance(name, str) or not _NAME.match(name) or name in (".", ".."):
        raise ValueError(f"invalid {kind} name {name!r}: use 1-64 letters, digits, '_', '.' "
                         "or '-', not starting with '.' or '-'")
    return name


def _finite(where: str, *values: float) -> None:
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
        raise ValueError(f"{where}: coordinates must be finite numbers, got {values}")


def check_points(where: str, points: Iterable[Point]) -> list[Point]:
    out = list(points)
    for i, p in enumerate(out):
        _finite(f"{where} point {i}", p.x, p.y, p.z)
    return out


def check_pose(where: str, pose: Pose2D) -> Pose2D:
    _finite(where, pose.x, pose.y, pose.theta)
    return pose


def check_nav_points(points: Iterable[NavPoint]) -> list[NavPoint]:
    """The nav points, checked: finite values, non-negative tolerances, unique names."""
    out = list(points)
    seen: dict[str, int] = {}
    for i, p in enumerate(out):
        _finite(f"nav point {i}", p.x, p.y, p.z, p.theta, p.error_x, p.error_y)
        if p.error_x < 0 or p.error_y < 0:
            raise ValueError(f"nav point {i}: error_x/error_y must be >= 0")
        if p.name:
            if p.name in seen:
                raise ValueError(f"nav point {i}: name {p.name!r} is already used by point "
                                 f"{seen[p.name]}; names are unique within a path")
            seen[p.name] = i
    return out


def check_wall(i: int, wall: VirtualWall) -> VirtualWall:
    if len(wall.points) < 2:
        raise ValueError(f"virtual wall {i} ({wall.name!r}): needs at least 2 points, "
                         f"got {len(wall.points)}")
    check_points(f"virtual wall {i}", wall.points)
    return wall


def check_area(i: int, area: ForbiddenArea) -> ForbiddenArea:
    if len(area.points) < 3:
        raise ValueError(f"forbidden area {i} ({area.name!r}): needs at least 3 points "
                         f"(a polygon), got {len(area.points)}")
    check_points(f"forbidden area {i}", area.points)
    return area


def read_nav_data(path: Path) -> MapNavData:
    """The data in ``path``; empty when the file does not exist.

    Raises:
        MapError: the file is unreadable or malformed (names the file and the field).
    """
    if not path.is_file():
        return MapNavData()
    try:
        return msgspec.yaml.decode(path.read_bytes(), type=MapNavData)
    except (OSError, msgspec.ValidationError, msgspec.DecodeError) as exc:
        raise MapError(f"{path}: {exc}") from exc


def write_nav_data(path: Path, data: MapNavData) -> None:
    """Write ``data`` atomically (a temporary file renamed over the old one)."""
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(msgspec.yaml.encode(data))
    tmp.replace(path)
