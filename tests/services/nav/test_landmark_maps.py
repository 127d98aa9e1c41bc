"""A map's landmarks.yaml travels with it: imported into the store, dropped when a new grid
replaces the map, carried by map archives both ways, and checked on the way in."""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import pytest
from zenros.errors import MapError
from zenros.maps import Reflector, load_landmarks, save_landmarks
from zenros.maps.archive import ArchiveError, Manifest, NavBundle, check_map, pack, read_archive
from zenros.services.nav.maps.mapmeta import MapRecord
from zenros.services.nav.maps.store import MapStore
from zenros.services.nav.params import DEMO_MAP

MARKS = [Reflector("a", 1.0, 2.0), Reflector("b", 3.0, -1.0, 0.03)]


def test_import_copies_the_landmarks_and_a_saved_grid_drops_them(tmp_path: Path) -> None:
    store = MapStore(tmp_path / "maps")
    store.import_map(DEMO_MAP)
    assert load_landmarks(store.folder("office")) == load_landmarks(DEMO_MAP)
    store.save_grid("office", store.load("office"), MapRecord())
    assert load_landmarks(store.folder("office")) == []


def test_a_bad_landmarks_file_refuses_the_import(tmp_path: Path) -> None:
    src = tmp_path / "src"
    src.mkdir()
    for name in ("office.yaml", "office.pgm"):
        (src / name).write_bytes((Path(DEMO_MAP).parent / name).read_bytes())
    (src / "landmarks.yaml").write_text("reflectors: [{id: a, x: 1}]\n")
    store = MapStore(tmp_path / "maps")
    with pytest.raises(MapError, match=r"landmarks.yaml: reflectors\[0\] must be a mapping"):
        store.import_map(src / "office.yaml")
    assert store.names() == []


def _archive(landmarks: bytes | None) -> bytes:
    folder = Path(DEMO_MAP).parent
    return pack("office", (folder / "office.yaml").read_bytes(), "office.pgm",
                (folder / "office.pgm").read_bytes(),
                Manifest(name="office", width=600, height=400, resolution=0.05,
                         origin=[-3.0, -9.75, 0.0]), NavBundle(), landmarks)


def test_archives_carry_the_landmarks(tmp_path: Path) -> None:
    save_landmarks(MARKS, tmp_path)
    data = _archive((tmp_path / "landmarks.yaml").read_bytes())
    assert "office/landmarks.yaml" in zipfile.ZipFile(io.BytesIO(data)).namelist()
    checked = check_map(read_archive(data), tmp_path / "in")
    assert load_landmarks(checked.yaml) == MARKS
    plain = check_map(read_archive(_archive(None)), tmp_path / "plain")
    assert load_landmarks(plain.yaml) == []


def test_an_archive_with_bad_landmarks_is_refused(tmp_path: Path) -> None:
    data = _archive(b"reflectors: [{id: a, x: 1, y: 2}, {id: a, x: 2, y: 3}]\n")
    with pytest.raises(ArchiveError, match="landmarks.yaml: reflector id 'a' is used twice"):
        check_map(read_archive(data), tmp_path / "in")
