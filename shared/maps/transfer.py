"""One stored map out of nav as an archive, and an archive into nav, over nav's services.

`export_map` packs a map the way ``GET /navigation/download_map_from_robot`` gives it (the
layout is `zenros.maps.archive`'s): its YAML and image read where nav keeps them, the
manifest, and its nav data (paths, nav points, the point connections that touch it).
`import_map` takes an archive's files, checks them whole in a folder of its own, then has nav
import that copy and sets the paths, nav points and connections, so a refused archive leaves
the stored maps untouched. The gateway (REST), the tasks service (``upload_map_action``,
``download_map_action``) and the schedule server use them.

Both take ``call(srv_type, request) -> response``, a blocking call of one of nav's services
(names relative to the robot: `NAV_SERVICES`), and raise `ArchiveError` with the HTTP status
that says why; a service error of ``call`` passes through, except a point connection nav
refuses (one of its points is on a map this robot does not have), which is skipped and said.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import msgspec
import yaml

from ..msgs import zenros_msgs as zm
from .archive import (
    MANIFEST,
    ArchiveError,
    ArchivePath,
    CheckedMap,
    Manifest,
    NavBundle,
    check_map,
    pack,
)
from .landmarks import landmarks_path

__all__ = ["NavCall", "export_map", "import_map", "read_map_files"]

NavCall = Callable[[Any, Any], Any]
"""``call(srv_type, request) -> response``: one of nav's services, blocking."""


def read_map_files(info: zm.MapInfo) -> tuple[bytes, str, bytes]:
    """The stored YAML (its image named bare) and image, read where nav keeps them."""
    try:
        doc = yaml.safe_load(Path(info.yaml_path).read_bytes())
        image = Path(info.image_path)
        data = image.read_bytes()
    except (OSError, yaml.YAMLError) as exc:
        raise ArchiveError(f"cannot read map {info.name!r}'s files where nav keeps them: "
                           f"{exc}", 502) from exc
    doc["image"] = image.name
    return yaml.safe_dump(doc, sort_keys=False).encode(), image.name, data


def read_landmarks_file(info: zm.MapInfo) -> bytes | None:
    """The stored map's ``landmarks.yaml`` (beside its YAML), or None when it has none."""
    path = landmarks_path(info.yaml_path)
    try:
        return path.read_bytes() if path.is_file() else None
    except OSError as exc:
        raise ArchiveError(f"cannot read map {info.name!r}'s {path.name}: {exc}", 502) from exc


def nav_bundle(call: NavCall, name: str) -> NavBundle:
    """Map ``name``'s paths (points and nav points) and the point connections touching it."""
    listed = call(zm.ListPaths, zm.ListPathsRequest(map_name=name))
    paths: list[ArchivePath] = []
    for ref in sorted(listed.paths, key=lambda p: p.path_name):
        if ref.map_name != name:
            continue
        path = call(zm.GetPath, zm.GetPathRequest(map_name=name, path_name=ref.path_name))
        points = call(zm.GetNavPoints, zm.GetNavPointsRequest(map_name=name,
                                                              path_name=ref.path_name))
        paths.append(ArchivePath(name=ref.path_name, points=list(path.points),
                                 nav_points=list(points.points)))
    conns = call(zm.ListPointConnections, zm.ListPointConnectionsRequest())
    touching = [c for c in conns.connections if any(p.map_name == name for p in c.points)]
    return NavBundle(paths=paths, connections=touching)


def export_map(call: NavCall, name: str) -> bytes:
    """Map ``name`` of nav's store as an archive (404 `ArchiveError` when nav has none)."""
    listed = call(zm.ListMaps, zm.ListMapsRequest(name=name))
    if not listed.maps:
        raise ArchiveError(f"unknown map {name!r}", 404)
    info: zm.MapInfo = listed.maps[0]
    yaml_text, image_name, image = read_map_files(info)
    manifest = Manifest(name=name, width=info.width, height=info.height,
                        resolution=info.resolution, origin=list(info.origin),
                        md5sum=info.md5sum)
    return pack(name, yaml_text, image_name, image, manifest, nav_bundle(call, name),
                read_landmarks_file(info))


def _renamed(conn: zm.PointConnection, old: str, new: str) -> list[zm.PointRef]:
    return [zm.PointRef(map_name=new if p.map_name == old else p.map_name,
                        path_name=p.path_name, index=p.index) for p in conn.points]


def _into_nav(call: NavCall, name: str, checked: CheckedMap, files: dict[str, bytes],
              refused: tuple[type[BaseException], ...]) -> dict[str, Any]:
    res = call(zm.ImportMap, zm.ImportMapRequest(name=name, yaml_path=str(checked.yaml),
                                                 overwrite=True))
    for path in checked.nav.paths:
        call(zm.SetPath, zm.SetPathRequest(map_name=name, path_name=path.name,
                                           points=path.points))
        call(zm.SetNavPoints, zm.SetNavPointsRequest(map_name=name, path_name=path.name,
                                                     points=path.nav_points))
    old = checked.yaml.stem
    if MANIFEST in files:
        old = msgspec.json.decode(files[MANIFEST], type=Manifest).name
    added, skipped = 0, []
    for conn in checked.nav.connections:
        try:
            call(zm.AddPointConnection, zm.AddPointConnectionRequest(
                points=_renamed(conn, old, name), type=conn.type,
                is_available=conn.is_available))
            added += 1
        except refused as exc:  # a point of another map that is not on this robot
            skipped.append(f"connection {conn.id or conn.oid}: "
                           f"{getattr(exc, 'detail', None) or exc}")
    return {"status": "ok", "name": res.info.name or name, "width": checked.width,
            "height": checked.height, "paths": len(checked.nav.paths),
            "connections": added, "skipped": skipped}


def import_map(call: NavCall, name: str, files: dict[str, bytes],
               refused: tuple[type[BaseException], ...] = (Exception,)) -> dict[str, Any]:
    """Check an archive's ``files`` (`zenros.maps.archive.read_archive`'s, or loose ones)
    whole, then import them into nav as ``name``: ``{"status": "ok", "name", "width",
    "height", "paths", "connections", "skipped"}``. ``refused``: the errors of ``call`` that
    mean nav refused one point connection (skipped, said in ``skipped``)."""
    with tempfile.TemporaryDirectory(prefix="zenros-map-import-") as tmp:
        checked = check_map(files, Path(tmp) / "map")
        return _into_nav(call, name, checked, files, refused)
