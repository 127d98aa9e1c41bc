"""The map folder's named poses (``poses.yaml``): where the robot starts and where it docks.

Format (all keys optional; x, y in metres and theta in radians, in the ``map`` frame)::

    start: {x: 1.0, y: 2.0, theta: 0.0}   # where the simulated robot appears
    dock: {x: 3.5, y: 1.0, theta: 3.1416} # the charging dock: the pose the robot docks at

``theta`` defaults to 0. The file sits beside the map YAML; a map without one has no
named poses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import yaml

from ..errors import MapError

__all__ = ["POSES_FILE", "MapPose", "MapPoses", "load_poses", "poses_path", "save_poses"]

POSES_FILE = "poses.yaml"
_KEYS = ("start", "dock")


class MapPose(NamedTuple):
    """A pose in the plane of ``map``: x, y (m), theta (rad, counter-clockwise)."""

    x: float
    y: float
    theta: float = 0.0


@dataclass(frozen=True)
class MapPoses:
    """The named poses of a map folder; ``None`` where the file does not give one."""

    start: MapPose | None = None
    dock: MapPose | None = None


def poses_path(map_path: str | Path) -> Path:
    """The poses file for a map YAML (or a map folder)."""
    p = Path(map_path)
    return (p if p.is_dir() else p.parent) / POSES_FILE


def _pose(value: Any, key: str, where: str) -> MapPose:
    if not isinstance(value, dict) or not {"x", "y"} <= value.keys():
        raise MapError(f"{where}: {key!r} must be a mapping with x, y (and theta), got {value!r}")
    extra = value.keys() - {"x", "y", "theta"}
    if extra:
        raise MapError(f"{where}: {key!r} has unknown keys {sorted(extra)}; expected x, y, theta")
    out = []
    for f in ("x", "y", "theta"):
        v = value.get(f, 0.0)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise MapError(f"{where}: '{key}.{f}' must be a finite number, got {v!r}")
        out.append(float(v))
    return MapPose(*out)


def load_poses(map_path: str | Path) -> MapPoses:
    """Read the poses beside a map YAML; empty `MapPoses` when there is no file.

    Raises:
        MapError: the file is not YAML or a pose is malformed (names the file and key).
    """
    path = poses_path(map_path)
    if not path.is_file():
        return MapPoses()
    where = str(path)
    try:
        doc = yaml.safe_load(path.read_text()) or {}
    except (OSError, yaml.YAMLError) as exc:
        raise MapError(f"{where}: cannot read poses: {exc}") from exc
    if not isinstance(doc, dict):
        raise MapError(f"{where}: expected a mapping with {', '.join(_KEYS)}")
    unknown = doc.keys() - set(_KEYS)
    if unknown:
        raise MapError(f"{where}: unknown keys {sorted(unknown)}; known: {', '.join(_KEYS)}")
    return MapPoses(**{k: _pose(doc[k], k, where) for k in _KEYS if k in doc})


def save_poses(poses: MapPoses, map_path: str | Path) -> Path:
    """Write the poses file beside a map YAML (or into a map folder); return its path."""
    path = poses_path(map_path)
    doc = {k: {"x": p.x, "y": p.y, "theta": p.theta}
           for k in _KEYS if (p := getattr(poses, k)) is not None}
    path.write_text(yaml.safe_dump(doc, sort_keys=False, default_flow_style=None))
    return path
