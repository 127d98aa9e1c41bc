"""MapMeta: the fields of a map_server YAML, read and checked, with errors naming file and key."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import yaml

from ..errors import MapError

__all__ = ["MapMeta", "Mode", "check_meta", "read_meta", "write_meta"]

Mode = Literal["trinary", "scale", "raw"]
_MODES: tuple[Mode, ...] = ("trinary", "scale", "raw")


@dataclass(frozen=True)
class MapMeta:
    """The metadata of a map (specs/tf-nav.md, Part D1).

    Attributes:
        image: the image path, resolved against the YAML's directory.
        resolution: metres per cell.
        origin: (x, y, yaw) of the lower-left cell's corner in ``map``.
        negate: swap the black/white meaning.
        occupied_thresh: probability above which a cell is occupied.
        free_thresh: probability below which a cell is free.
        mode: ``trinary`` (default), ``scale`` or ``raw``.
    """

    image: Path
    resolution: float
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    negate: bool = False
    occupied_thresh: float = 0.65
    free_thresh: float = 0.196
    mode: Mode = "trinary"


def check_meta(meta: MapMeta, where: str) -> None:
    """Raise `MapError` naming ``where`` and the field when a value is out of range."""
    if not (math.isfinite(meta.resolution) and meta.resolution > 0):
        raise MapError(f"{where}: 'resolution' must be a positive number, got {meta.resolution}")
    if not all(math.isfinite(v) for v in meta.origin):
        raise MapError(f"{where}: 'origin' must be finite [x, y, yaw], got {list(meta.origin)}")
    for key in ("occupied_thresh", "free_thresh"):
        v = getattr(meta, key)
        if not (0.0 <= v <= 1.0):
            raise MapError(f"{where}: {key!r} must be within 0..1, got {v}")
    if meta.free_thresh >= meta.occupied_thresh:
        raise MapError(f"{where}: 'free_thresh' ({meta.free_thresh}) must be below "
                       f"'occupied_thresh' ({meta.occupied_thresh})")
    if meta.mode not in _MODES:
        raise MapError(f"{where}: 'mode' must be one of {', '.join(_MODES)}, got {meta.mode!r}")


def _number(doc: dict[str, Any], key: str, where: str) -> float:
    v = doc[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise MapError(f"{where}: {key!r} must be a number, got {v!r}")
    return float(v)


def _required(doc: dict[str, Any], key: str, where: str) -> Any:
    if key not in doc:
        raise MapError(f"{where}: missing required key {key!r}")
    return doc[key]


def read_meta(path: str | Path) -> MapMeta:
    """Read and check a map_server YAML file.

    Raises:
        MapError: the file is unreadable, not YAML, or a key is missing or invalid
            (the message names the file and the key).
    """
    path = Path(path)
    where = str(path)
    try:
        doc = yaml.safe_load(path.read_text())
    except OSError as exc:
        raise MapError(f"{where}: cannot read map YAML: {exc.strerror or exc}") from exc
    except yaml.YAMLError as exc:
        raise MapError(f"{where}: not valid YAML: {exc}") from exc
    if not isinstance(doc, dict):
        raise MapError(f"{where}: expected a mapping of map keys, got {type(doc).__name__}")
    image = _required(doc, "image", where)
    if not isinstance(image, str) or not image:
        raise MapError(f"{where}: 'image' must be a file name, got {image!r}")
    for key in ("resolution", "origin", "occupied_thresh", "free_thresh", "negate"):
        _required(doc, key, where)
    origin = doc["origin"]
    if (not isinstance(origin, list) or len(origin) != 3
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in origin)):
        raise MapError(f"{where}: 'origin' must be a list of 3 numbers [x, y, yaw], got {origin!r}")
    negate = doc["negate"]
    if negate not in (0, 1) and not isinstance(negate, bool):
        raise MapError(f"{where}: 'negate' must be 0 or 1, got {negate!r}")
    mode = doc.get("mode", "trinary")
    if mode not in _MODES:
        raise MapError(f"{where}: 'mode' must be one of {', '.join(_MODES)}, got {mode!r}")
    meta = MapMeta(
        image=(path.parent / image).resolve() if not Path(image).is_absolute() else Path(image),
        resolution=_number(doc, "resolution", where),
        origin=(float(origin[0]), float(origin[1]), float(origin[2])),
        negate=bool(negate),
        occupied_thresh=_number(doc, "occupied_thresh", where),
        free_thresh=_number(doc, "free_thresh", where),
        mode=mode,
    )
    check_meta(meta, where)
    return meta


def write_meta(meta: MapMeta, path: str | Path) -> None:
    """Write ``meta`` as a map_server YAML; the image is named relative to the YAML when it can be."""
    path = Path(path)
    check_meta(meta, str(path))
    try:
        image = str(Path(meta.image).resolve().relative_to(path.parent.resolve()))
    except ValueError:
        image = str(meta.image)
    doc = {
        "image": image,
        "mode": meta.mode,
        "resolution": meta.resolution,
        "origin": [float(v) for v in meta.origin],
        "negate": int(meta.negate),
        "occupied_thresh": meta.occupied_thresh,
        "free_thresh": meta.free_thresh,
    }
    path.write_text(yaml.safe_dump(doc, sort_keys=False, default_flow_style=None))
