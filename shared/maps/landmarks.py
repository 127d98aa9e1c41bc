"""The map folder's landmarks (``landmarks.yaml``): retro-reflectors the laser sees.

Format (metres in the ``map`` frame; ``radius`` optional, default `DEFAULT_RADIUS`)::

    reflectors:
      - {id: r1, x: -2.425, y: 0.5}              # a strip on a wall: its centre on the face
      - {id: r2, x: 1.0, y: 1.175, radius: 0.04}

A reflector is a retro-reflective strip on a wall or round a post, seen by the laser as
strong returns within ``radius`` of its centre (the simulated laser, docs/chassis.md) and
used to relocalise (docs/nav.md, "Landmarks"). Ids are unique strings (an integer is taken
as its digits). The file sits beside the map YAML, like ``poses.yaml``; a map without one
has no landmarks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from ..errors import MapError

__all__ = ["DEFAULT_RADIUS", "LANDMARKS_FILE", "Reflector", "landmarks_path", "load_landmarks",
           "save_landmarks"]

LANDMARKS_FILE = "landmarks.yaml"
DEFAULT_RADIUS = 0.05
MAX_RADIUS = 0.5
_KEYS = ("id", "x", "y", "radius")


@dataclass(frozen=True)
class Reflector:
    """A reflector's centre (x, y) in ``map`` and its ``radius`` (m)."""

    id: str
    x: float
    y: float
    radius: float = DEFAULT_RADIUS


def landmarks_path(map_path: str | Path) -> Path:
    """The landmarks file for a map YAML (or a map folder)."""
    p = Path(map_path)
    return (p if p.is_dir() else p.parent) / LANDMARKS_FILE


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise MapError(f"{where} must be a finite number, got {value!r}")
    return float(value)


def _reflector(item: Any, i: int, where: str) -> Reflector:
    at = f"{where}: reflectors[{i}]"
    if not isinstance(item, dict) or not {"id", "x", "y"} <= item.keys():
        raise MapError(f"{at} must be a mapping with id, x, y (and radius), got {item!r}")
    extra = item.keys() - set(_KEYS)
    if extra:
        raise MapError(f"{at} has unknown keys {sorted(extra)}; expected {', '.join(_KEYS)}")
    rid = item["id"]
    if isinstance(rid, bool) or not isinstance(rid, (str, int)) or not str(rid).strip():
        raise MapError(f"{at}.id must be a non-empty string, got {rid!r}")
    radius = _number(item.get("radius", DEFAULT_RADIUS), f"{at}.radius")
    if not 0 < radius <= MAX_RADIUS:
        raise MapError(f"{at}.radius must be in (0, {MAX_RADIUS}] m, got {radius:g}")
    return Reflector(str(rid).strip(), _number(item["x"], f"{at}.x"),
                     _number(item["y"], f"{at}.y"), radius)


def check_landmarks(reflectors: list[Reflector], where: str) -> None:
    """Raise `MapError` if two reflectors share an id."""
    seen: set[str] = set()
    for r in reflectors:
        if r.id in seen:
            raise MapError(f"{where}: reflector id {r.id!r} is used twice; ids must be unique")
        seen.add(r.id)


def load_landmarks(map_path: str | Path) -> list[Reflector]:
    """Read the reflectors beside a map YAML; an empty list when there is no file.

    Raises:
        MapError: the file is not YAML or a reflector is malformed (names the file and
            the entry).
    """
    path = landmarks_path(map_path)
    if not path.is_file():
        return []
    where = str(path)
    try:
        doc = yaml.safe_load(path.read_text()) or {}
    except (OSError, yaml.YAMLError) as exc:
        raise MapError(f"{where}: cannot read landmarks: {exc}") from exc
    if not isinstance(doc, dict):
        raise MapError(f"{where}: expected a mapping with 'reflectors'")
    unknown = doc.keys() - {"reflectors"}
    if unknown:
        raise MapError(f"{where}: unknown keys {sorted(unknown)}; known: reflectors")
    items = doc.get("reflectors") or []
    if not isinstance(items, list):
        raise MapError(f"{where}: 'reflectors' must be a list, got {type(items).__name__}")
    out = [_reflector(item, i, where) for i, item in enumerate(items)]
    check_landmarks(out, where)
    return out


def save_landmarks(reflectors: list[Reflector], map_path: str | Path) -> Path:
    """Write the landmarks file beside a map YAML (or into a map folder); return its path.

    Raises:
        MapError: two reflectors share an id.
    """
    path = landmarks_path(map_path)
    check_landmarks(reflectors, str(path))
    doc = {"reflectors": [{"id": r.id, "x": r.x, "y": r.y, "radius": r.radius}
                          for r in reflectors]}
    path.write_text(yaml.safe_dump(doc, sort_keys=False, default_flow_style=None))
    return path
