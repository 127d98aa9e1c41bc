"""`MapShelf`: the map archives a schedule server keeps, one file each, and an index.

``<dir>/<map_id>.zip`` holds an archive as it was put (checked first: `zenros.maps.archive`),
``<dir>/index.json`` what `MapArchiveInfo` says of each. Writes go to a temporary file
renamed into place, so a server stopped mid-write loses nothing already kept.
"""

from __future__ import annotations

import json
import os
import tempfile
import threading
import uuid
from pathlib import Path

import msgspec
from zenros.maps.archive import MANIFEST, ArchiveError, Manifest, check_map, read_archive
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.zenros_msgs.schedule import MapArchiveInfo

__all__ = ["MapShelf"]

INDEX = "index.json"


def _write(path: Path, data: bytes) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


class MapShelf:
    """The archives in ``folder``, by map id."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        folder.mkdir(parents=True, exist_ok=True)
        self._lock = threading.Lock()
        self._index: dict[str, MapArchiveInfo] = {}
        index = folder / INDEX
        if index.exists():
            raw = json.loads(index.read_text())
            self._index = {k: msgspec.convert(v, MapArchiveInfo) for k, v in raw.items()
                           if (folder / f"{k}.zip").exists()}

    def put(self, data: bytes, now: Time) -> MapArchiveInfo:
        """Check ``data`` as a map archive and keep it; `ArchiveError` when it is not one."""
        files = read_archive(data)
        with tempfile.TemporaryDirectory(prefix="zenros-schedule-check-") as tmp:
            checked = check_map(files, Path(tmp) / "map")
        name, md5, resolution = checked.yaml.stem, "", 0.0
        if MANIFEST in files:  # check_map has checked it against the image
            manifest = msgspec.json.decode(files[MANIFEST], type=Manifest)
            name, md5, resolution = manifest.name, manifest.md5sum, manifest.resolution
        info = MapArchiveInfo(map_id=uuid.uuid4().hex, name=name, size=len(data),
                              width=checked.width, height=checked.height,
                              resolution=resolution, md5sum=md5, stamp=now)
        with self._lock:
            _write(self.folder / f"{info.map_id}.zip", data)
            self._index[info.map_id] = info
            self._save_index()
        return info

    def get(self, map_id: str) -> tuple[MapArchiveInfo, bytes]:
        """The archive kept as ``map_id``; `ArchiveError` (404) when there is none."""
        with self._lock:
            info = self._index.get(map_id)
        if info is None:
            raise ArchiveError(f"no map {map_id!r} on this schedule server", 404)
        return info, (self.folder / f"{map_id}.zip").read_bytes()

    def list(self) -> list[MapArchiveInfo]:
        with self._lock:
            return sorted(self._index.values(), key=lambda i: (i.stamp.sec, i.stamp.nanosec))

    def _save_index(self) -> None:
        _write(self.folder / INDEX, json.dumps(
            {k: msgspec.to_builtins(v) for k, v in self._index.items()}, indent=1).encode())
