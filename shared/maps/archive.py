"""Map archives (docs/robot-api.md §6.3 ``download_map_from_robot``, ``upload_map_to_robot``):
one map's YAML, its image, a manifest and its nav data (paths, nav points, point connections)
in a zip; and the checks an archive (or loose files) passes before nav imports it.

Layout (``<name>`` is the map's name)::

    <name>/<name>.yaml      map_server YAML, ``image: <name>.pgm`` (or .png)
    <name>/<name>.pgm       the image as nav stores it
    <name>/map.json         `Manifest`: name, width, height, resolution, origin, md5sum
    <name>/nav.json         `NavBundle`: paths (points and nav points), point connections
    <name>/landmarks.yaml   the map's reflectors (`zenros.maps.landmarks`), when it has any

No HTTP here: a refused archive is an `ArchiveError` carrying the HTTP status that says why
(the gateway answers with it; the schedule server and the tasks service word it).
"""

from __future__ import annotations

import hashlib
import io
import stat
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

import msgspec
import yaml

from ..errors import MapError
from ..msgs.geometry_msgs import Point
from ..msgs.zenros_msgs.nav import NavPoint, PointConnection
from . import load_map, read_meta
from .landmarks import LANDMARKS_FILE, load_landmarks

__all__ = ["MAX_ARCHIVE", "ArchiveError", "ArchivePath", "CheckedMap", "Manifest", "NavBundle",
           "check_map", "pack", "read_archive"]

MAX_ARCHIVE = 64 * 1024 * 1024      # bytes of an upload, and of an archive's files unpacked
MAX_MEMBERS = 64
IMAGE_SUFFIXES = (".pgm", ".png")
MANIFEST = "map.json"
NAV = "nav.json"


class ArchiveError(Exception):
    """An archive or its files refused; ``status`` is the HTTP code that says why."""

    def __init__(self, detail: str, status: int = 400) -> None:
        super().__init__(detail)
        self.detail = detail
        self.status = status


class Manifest(msgspec.Struct, forbid_unknown_fields=True):
    """The map as the robot stored it: checked against the image on the way in."""

    name: str
    width: int
    height: int
    resolution: float
    origin: list[float]
    md5sum: str = ""


class ArchivePath(msgspec.Struct, forbid_unknown_fields=True):
    name: str
    points: list[Point] = msgspec.field(default_factory=list)
    nav_points: list[NavPoint] = msgspec.field(default_factory=list)


class NavBundle(msgspec.Struct, forbid_unknown_fields=True):
    """The map's paths (recorded points and nav points) and the point connections that
    touch it."""

    paths: list[ArchivePath] = msgspec.field(default_factory=list)
    connections: list[PointConnection] = msgspec.field(default_factory=list)


@dataclass(frozen=True)
class CheckedMap:
    """A map that passed every check, written under ``folder`` (``yaml`` names it)."""

    yaml: Path
    width: int
    height: int
    nav: NavBundle


def pack(name: str, yaml_text: bytes, image_name: str, image: bytes, manifest: Manifest,
         nav: NavBundle, landmarks: bytes | None = None) -> bytes:
    """The archive of one map (see the module's layout); ``landmarks``: the text of its
    ``landmarks.yaml``, if it has one."""
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", compression=zipfile.ZIP_DEFLATED) as z:
        z.writestr(f"{name}/{name}.yaml", yaml_text)
        z.writestr(f"{name}/{image_name}", image)
        z.writestr(f"{name}/{MANIFEST}", msgspec.json.encode(manifest))
        z.writestr(f"{name}/{NAV}", msgspec.json.encode(nav))
        if landmarks is not None:
            z.writestr(f"{name}/{LANDMARKS_FILE}", landmarks)
    return out.getvalue()


def _member_name(raw: str) -> str:
    """A member's file name, or `ArchiveError` for one that would leave the folder."""
    text = raw.replace("\\", "/")
    p = PurePosixPath(text)
    if not text or "\x00" in text or p.is_absolute() or ".." in p.parts or (
            len(text) > 1 and text[1] == ":"):
        raise ArchiveError(f"archive member {raw!r} leaves the map's folder (absolute, "
                           "a drive or '..'): refused")
    return p.name


def read_archive(data: bytes) -> dict[str, bytes]:
    """The files of a zip archive by file name (folders flattened), checked: no member
    leaves the folder, no links, at most `MAX_MEMBERS` files and `MAX_ARCHIVE` bytes
    unpacked, no name twice."""
    try:
        z = zipfile.ZipFile(io.BytesIO(data))
    except zipfile.BadZipFile as exc:
        raise ArchiveError(f"not a zip archive: {exc}") from exc
    files: dict[str, bytes] = {}
    total = 0
    with z:
        infos = z.infolist()
        if len(infos) > MAX_MEMBERS:
            raise ArchiveError(f"the archive has {len(infos)} members (limit {MAX_MEMBERS})")
        for info in infos:
            name = _member_name(info.filename)
            if info.is_dir():
                continue
            if stat.S_ISLNK(info.external_attr >> 16):
                raise ArchiveError(f"archive member {info.filename!r} is a symbolic link: "
                                   "refused")
            total += info.file_size
            if total > MAX_ARCHIVE:
                raise ArchiveError(f"the archive unpacks to over {MAX_ARCHIVE} bytes", 413)
            if name in files:
                raise ArchiveError(f"the archive has two files named {name!r}")
            try:
                content = z.read(info)
            except (zipfile.BadZipFile, ValueError, NotImplementedError) as exc:
                raise ArchiveError(f"archive member {info.filename!r} is damaged: {exc}"
                                   ) from exc
            if len(content) != info.file_size:
                raise ArchiveError(f"archive member {info.filename!r} is damaged")
            files[name] = content
    return files


def _one(files: Mapping[str, bytes], suffixes: tuple[str, ...], what: str) -> str:
    found = sorted(n for n in files if n.lower().endswith(suffixes) and n != LANDMARKS_FILE)
    if len(found) != 1:
        has = ", ".join(sorted(files)) or "nothing"
        raise ArchiveError(f"expected one {what} ({'/'.join(suffixes)}), found "
                           f"{len(found)}; the upload holds {has}")
    return found[0]


def check_map(files: Mapping[str, bytes], folder: Path) -> CheckedMap:
    """Check a map's files (by file name) and write them into ``folder`` (empty, outside
    the maps store): one YAML whose ``image`` is one of the files, by name; an image that
    decodes; the manifest, when there is one, matching the image's size and the YAML's
    resolution; nav.json, when there is one, of the right shape; landmarks.yaml, when there
    is one, readable (`zenros.maps.landmarks`).

    Raises:
        ArchiveError: what is wrong, naming the file and the field.
    """
    for name in files:
        _member_name(name)
    yaml_name = _one(files, (".yaml", ".yml"), "map YAML")
    try:
        doc = yaml.safe_load(files[yaml_name])
    except yaml.YAMLError as exc:
        raise ArchiveError(f"{yaml_name}: not valid YAML: {exc}") from exc
    if not isinstance(doc, dict):
        raise ArchiveError(f"{yaml_name}: not a map_server YAML (a mapping of map keys)")
    image = doc.get("image")
    if not isinstance(image, str) or PurePosixPath(image.replace("\\", "/")).name != image:
        raise ArchiveError(f"{yaml_name}: 'image' must name a file of the upload by its "
                           f"bare name, got {image!r}")
    if image not in files:
        raise ArchiveError(f"{yaml_name}: 'image' names {image!r}, which the upload does "
                           f"not hold (it holds {', '.join(sorted(files))})")
    if not image.lower().endswith(IMAGE_SUFFIXES):
        raise ArchiveError(f"{yaml_name}: 'image' {image!r} is not a .pgm or .png")
    folder.mkdir(parents=True, exist_ok=True)
    for name in (yaml_name, image):
        (folder / name).write_bytes(files[name])
    try:
        meta = read_meta(folder / yaml_name)
        grid = load_map(folder / yaml_name)
    except MapError as exc:
        raise ArchiveError(str(exc).replace(str(folder) + "/", "")) from exc
    if MANIFEST in files:
        try:
            manifest = msgspec.json.decode(files[MANIFEST], type=Manifest)
        except msgspec.DecodeError as exc:
            raise ArchiveError(f"{MANIFEST}: {exc}") from exc
        if (manifest.width, manifest.height) != (grid.width, grid.height):
            raise ArchiveError(f"{image}: the image is {grid.width}x{grid.height} pixels, "
                               f"but {MANIFEST} says {manifest.width}x{manifest.height}")
        if abs(manifest.resolution - meta.resolution) > 1e-9:
            raise ArchiveError(f"{yaml_name}: resolution {meta.resolution} differs from "
                               f"{MANIFEST}'s {manifest.resolution}")
        md5 = hashlib.md5(files[image]).hexdigest()
        if manifest.md5sum and manifest.md5sum != md5:
            raise ArchiveError(f"{image}: its md5sum {md5} is not {MANIFEST}'s "
                               f"{manifest.md5sum} (damaged on the way)")
    nav = NavBundle()
    if NAV in files:
        try:
            nav = msgspec.json.decode(files[NAV], type=NavBundle)
        except msgspec.DecodeError as exc:
            raise ArchiveError(f"{NAV}: {exc}") from exc
    if LANDMARKS_FILE in files:
        (folder / LANDMARKS_FILE).write_bytes(files[LANDMARKS_FILE])
        try:
            load_landmarks(folder)
        except MapError as exc:
            raise ArchiveError(str(exc).replace(str(folder) + "/", "")) from exc
    unknown = sorted(set(files) - {yaml_name, image, MANIFEST, NAV, LANDMARKS_FILE})
    if unknown:
        raise ArchiveError(f"the upload holds files a map has not: {', '.join(unknown)}")
    return CheckedMap(yaml=folder / yaml_name, width=grid.width, height=grid.height, nav=nav)
