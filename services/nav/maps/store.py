"""MapStore: the maps folder ``$ZENROS_HOME/maps/<name>/`` (map YAML + image + nav data).

Each map folder holds ``<name>.yaml`` and its image (``<name>.pgm`` or ``.png``) in
map_server format, the simulator's ``poses.yaml`` and the reflectors' ``landmarks.yaml``
when the source map had them,
``nav.yaml`` (`MapNavData`) and, for a saved grid, ``record.yml`` (`MapRecord`: type,
levels, built by SLAM). Importing copies a map_server map in; the source is checked
first (`zenros.maps.load_map`), so a bad file never replaces a good one.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import threading
from collections.abc import Callable
from pathlib import Path

import msgspec
from zenros.errors import MapError, MapItemNotFoundError
from zenros.maps import (
    GridMap,
    MapMeta,
    encode_image,
    grid_to_pixels,
    landmarks_path,
    load_landmarks,
    load_map,
    load_poses,
    poses_path,
    read_meta,
    write_meta,
)
from zenros.maps.meta import check_meta
from zenros.msgs.geometry_msgs import Pose2D
from zenros.msgs.zenros_msgs.nav import MapInfo

from .mapmeta import RECORD_FILE, MapRecord, check_record, read_record, write_record
from .navdata import NAV_FILE, MapNavData, check_name, read_nav_data, write_nav_data

__all__ = ["MapStore"]


class MapStore:
    """The maps under ``root``; thread-safe for the service handlers that share it."""

    def __init__(self, root: Path) -> None:
        self.root = Path(root)
        self.root.mkdir(parents=True, exist_ok=True)
        self._lock = threading.RLock()
        self._nav: dict[str, MapNavData] = {}

    # ------------------------------------------------------------------ maps

    def folder(self, name: str) -> Path:
        return self.root / check_name("map", name)

    def yaml_path(self, name: str) -> Path:
        return self.folder(name) / f"{name}.yaml"

    def names(self) -> list[str]:
        """The stored maps, sorted."""
        return sorted(p.parent.name for p in self.root.glob("*/*.yaml")
                      if p.stem == p.parent.name)

    def require(self, name: str) -> str:
        """``name`` if such a map is stored, else a `MapError` listing the known ones."""
        if not name or not self.yaml_path(name).is_file():
            known = ", ".join(self.names()) or "none"
            raise MapItemNotFoundError(f"unknown map {name!r}; known maps: {known}")
        return name

    def load(self, name: str) -> GridMap:
        """The stored map's grid (raises `MapError` naming the file and field)."""
        return load_map(self.yaml_path(self.require(name)))

    def md5sum(self, name: str) -> str:
        meta = read_meta(self.yaml_path(self.require(name)))
        return hashlib.md5(meta.image.read_bytes()).hexdigest()

    def info(self, name: str, grid: GridMap | None = None) -> MapInfo:
        """A stored map's metadata (reads the YAML; the size from ``grid`` or the image)."""
        path = self.yaml_path(self.require(name))
        meta = read_meta(path)
        if grid is None:
            grid = load_map(path)
        try:
            rec = self.record(name)
        except MapError:
            rec = MapRecord()  # a damaged record: the map itself is still good
        return MapInfo(
            name=name, resolution=meta.resolution, origin=list(meta.origin),
            width=grid.width, height=grid.height, occupied_thresh=meta.occupied_thresh,
            free_thresh=meta.free_thresh, negate=int(meta.negate), mode=meta.mode,
            md5sum=hashlib.md5(meta.image.read_bytes()).hexdigest(), type=rec.type,
            levels=list(rec.levels), slam_type=rec.slam_type,
            yaml_path=str(path.resolve()), image_path=str(meta.image))

    def record(self, name: str) -> MapRecord:
        """The map's `MapRecord` (defaults for an imported map; `MapError` if malformed)."""
        return read_record(self.folder(self.require(name)))

    def save_grid(self, name: str, grid: GridMap, record: MapRecord) -> str:
        """Store ``grid`` as the map ``name`` as map_saver writes it (trinary: 254 free,
        0 occupied, 205 unknown; thresholds 0.65/0.196), a PGM (the YAML's image) and a PNG
        of the same pixels, with ``record``. A map of that name is replaced, its nav data
        kept. Returns the name."""
        name = check_name("map", name)
        if grid.width == 0 or grid.height == 0:
            raise ValueError(f"map {name!r}: the grid is empty ({grid.width}x{grid.height})")
        pixels = grid_to_pixels(grid.grid)
        ox, oy, oyaw = (float(v) for v in grid.origin)
        with self._lock:
            dst = self.folder(name)
            meta = MapMeta(image=dst / f"{name}.pgm", resolution=grid.resolution,
                           origin=(ox, oy, oyaw), negate=False, occupied_thresh=0.65,
                           free_thresh=0.196, mode="trinary")
            check_meta(meta, f"map {name!r}")  # before any file: a bad grid changes nothing
            check_record(record)
            dst.mkdir(parents=True, exist_ok=True)
            for old in dst.glob(f"{name}.*"):
                if old.suffix == ".bmp":
                    old.unlink(missing_ok=True)
            _atomic(dst / f"{name}.pgm", lambda tmp: tmp.write_bytes(encode_image(pixels, "pgm")))
            _atomic(dst / f"{name}.png", lambda tmp: tmp.write_bytes(encode_image(pixels, "png")))
            _atomic(dst / RECORD_FILE, lambda tmp: write_record(tmp, record))
            # the YAML last: a reader that sees it sees the image and the record it names
            _atomic(self.yaml_path(name), lambda tmp: write_meta(meta, tmp))
            poses_path(dst).unlink(missing_ok=True)  # the simulator's poses were another map's
            landmarks_path(dst).unlink(missing_ok=True)  # so were the reflectors' places
            self._nav.pop(name, None)
        return name

    def import_map(self, source: str | Path, name: str = "", *, overwrite: bool = True) -> str:
        """Copy a map_server map into the store as ``name`` (default: the YAML's stem).

        The map is loaded first, so a bad source raises `MapError` and changes nothing.
        An existing map's nav data is kept. Returns the name.
        """
        src = Path(source)
        name = check_name("map", name or src.stem)
        meta = read_meta(src)
        load_map(src)  # the image must decode too
        load_landmarks(src)  # and the reflectors, if any, must read
        with self._lock:
            dst = self.folder(name)
            if self.yaml_path(name).is_file():
                if not overwrite:
                    raise MapError(f"map {name!r} already exists (set overwrite to replace it)")
                if self.yaml_path(name).resolve() == src.resolve():
                    return name
            dst.mkdir(parents=True, exist_ok=True)
            image = dst / f"{name}{meta.image.suffix.lower() or '.pgm'}"
            for old in dst.glob(f"{name}.*"):
                if old.suffix in (".pgm", ".png", ".bmp") and old != image:
                    old.unlink(missing_ok=True)
            # Each file is written aside and renamed into place: robots of one host share the
            # store and import the same map at once (fleet.yaml), and a reader must never see
            # a file half written by another process.
            _atomic(image, lambda tmp: shutil.copyfile(meta.image, tmp))
            _atomic(self.yaml_path(name), lambda tmp: write_meta(MapMeta(
                image=image, resolution=meta.resolution, origin=meta.origin,
                negate=meta.negate, occupied_thresh=meta.occupied_thresh,
                free_thresh=meta.free_thresh, mode=meta.mode), tmp))
            (dst / RECORD_FILE).unlink(missing_ok=True)  # another map's record (a saved grid)
            poses = load_poses(src)
            if poses_path(src).is_file():
                _atomic(poses_path(dst), lambda tmp: shutil.copyfile(poses_path(src), tmp))
            if landmarks_path(src).is_file():
                _atomic(landmarks_path(dst),
                        lambda tmp: shutil.copyfile(landmarks_path(src), tmp))
            nav_file = dst / NAV_FILE
            if not nav_file.is_file() and poses.dock is not None:
                d = poses.dock
                nav = MapNavData(charge_pose=Pose2D(x=d.x, y=d.y, theta=d.theta))
                _atomic(nav_file, lambda tmp: write_nav_data(tmp, nav))
            self._nav.pop(name, None)
        return name

    def delete(self, name: str) -> None:
        with self._lock:
            shutil.rmtree(self.folder(self.require(name)))
            self._nav.pop(name, None)

    # ------------------------------------------------------------------ nav data

    def nav_data(self, name: str) -> MapNavData:
        """The map's nav data (cached; a copy is not made, so treat it as read-only)."""
        with self._lock:
            data = self._nav.get(name)
            if data is None:
                data = read_nav_data(self.folder(self.require(name)) / NAV_FILE)
                self._nav[name] = data
            return data

    def update_nav_data(self, name: str, change: Callable[[MapNavData], object]
                        ) -> MapNavData:
        """Apply ``change`` to a copy of the map's nav data, persist it, and return it.

        ``change`` may raise (ValueError, MapError) to refuse; nothing is written then.
        What it returns is ignored.
        """
        with self._lock:
            data = msgspec.structs.replace(self.nav_data(name))
            data.paths = {k: msgspec.structs.replace(v) for k, v in data.paths.items()}
            data.virtual_walls = list(data.virtual_walls)
            data.forbidden_areas = list(data.forbidden_areas)
            change(data)
            write_nav_data(self.folder(name) / NAV_FILE, data)
            self._nav[name] = data
            return data


def _atomic(path: Path, write: Callable[[Path], object]) -> None:
    """``write`` a temporary file beside ``path``, then rename it to ``path`` (atomic)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
