"""MapStore and MapServer: importing maps into the maps folder, nav data on disk, switching."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from zenros.errors import MapError
from zenros.maps import GridMap, save_map
from zenros.msgs.geometry_msgs import Point, Pose2D
from zenros.msgs.zenros_msgs.nav import NavPoint, VirtualWall
from zenros.services.nav.maps.navdata import (
    NAV_FILE,
    MapNavData,
    StoredPath,
    check_name,
    read_nav_data,
)
from zenros.services.nav.maps.server import MapServer
from zenros.services.nav.maps.store import MapStore
from zenros.services.nav.params import DEMO_MAP


def make_map(folder: Path, name: str, value: int = 0) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    grid = np.full((10, 20), value, dtype=np.int8)
    save_map(GridMap(grid, 0.1, (1.0, 2.0, 0.0)), folder / f"{name}.yaml")
    return folder / f"{name}.yaml"


def test_import_copies_the_map_and_its_dock_becomes_the_charge_pose(tmp_path: Path) -> None:
    store = MapStore(tmp_path / "maps")
    assert store.import_map(DEMO_MAP) == "office"
    folder = tmp_path / "maps" / "office"
    assert {p.name for p in folder.iterdir()} == {"office.yaml", "office.pgm", "poses.yaml",
                                                  "landmarks.yaml", NAV_FILE}
    assert store.load("office").grid.shape == (400, 600)
    assert store.nav_data("office").charge_pose == Pose2D(x=22.0, y=-8.78, theta=-np.pi / 2)
    info = store.info("office")
    assert info.width == 600 and info.md5sum == store.md5sum("office")


def test_a_bad_source_changes_nothing(tmp_path: Path) -> None:
    store = MapStore(tmp_path / "maps")
    src = make_map(tmp_path / "src", "lab")
    store.import_map(src)
    before = store.md5sum("lab")
    make_map(tmp_path / "src2", "lab", value=100)
    (tmp_path / "src2" / "lab.pgm").write_bytes(b"P5\n2 2\n255\n")  # truncated pixels
    with pytest.raises(MapError, match="lab.pgm"):
        store.import_map(tmp_path / "src2" / "lab.yaml")
    assert store.md5sum("lab") == before
    with pytest.raises(MapError, match="unknown map 'attic'; known maps: lab"):
        store.load("attic")
    with pytest.raises(ValueError, match="invalid map name"):
        store.import_map(src, "../evil")


def test_nav_data_round_trip_and_refused_changes(tmp_path: Path) -> None:
    store = MapStore(tmp_path / "maps")
    store.import_map(make_map(tmp_path / "src", "lab"))
    wall = VirtualWall(name="w", points=[Point(x=1.0), Point(x=2.0, y=1.0)])

    def change(d: MapNavData) -> None:
        d.paths["p"] = StoredPath(nav_points=[NavPoint(name="a", x=1.5)])
        d.virtual_walls = [wall]

    store.update_nav_data("lab", change)
    data = read_nav_data(tmp_path / "maps" / "lab" / NAV_FILE)
    assert data.paths["p"].nav_points[0].x == 1.5 and data.virtual_walls == [wall]

    def refuse(d: MapNavData) -> None:
        d.virtual_walls.clear()
        raise ValueError("no")

    with pytest.raises(ValueError):
        store.update_nav_data("lab", refuse)
    assert store.nav_data("lab").virtual_walls == [wall]  # the refused change left no trace
    (tmp_path / "maps" / "lab" / NAV_FILE).write_text("paths: 3\n")
    with pytest.raises(MapError, match=r"nav\.yaml.*paths"):
        read_nav_data(tmp_path / "maps" / "lab" / NAV_FILE)


def test_names_are_checked() -> None:
    assert check_name("map", "office-2.v1") == "office-2.v1"
    for bad in ("", ".", "..", "a/b", "-x", "a" * 65, "a b"):
        with pytest.raises(ValueError):
            check_name("map", bad)


def test_switch_keeps_the_current_map_on_failure(tmp_path: Path) -> None:
    seen: list[str] = []
    server = MapServer(MapStore(tmp_path / "maps"), lambda name, grid: seen.append(name))
    server.start(make_map(tmp_path / "src", "lab"))
    server.store.import_map(make_map(tmp_path / "src", "hall"))
    (tmp_path / "maps" / "hall" / "hall.pgm").unlink()
    with pytest.raises(MapError, match="hall"):
        server.switch("hall")
    assert server.current == "lab" and seen == ["lab"]
    assert server.resolve("") == "lab"


IMPORTER = """
import sys
from zenros.services.nav.maps.store import MapStore
store = MapStore(sys.argv[1])
for _ in range(int(sys.argv[3])):
    store.import_map(sys.argv[2])
    store.load("office")  # what another robot's nav reads meanwhile
"""


def test_processes_importing_one_map_at_once_never_read_it_half_written(tmp_path: Path) -> None:
    """fleet.yaml: every robot's nav imports the demo map into the host's one store at start."""
    import subprocess
    import sys

    procs = [subprocess.Popen([sys.executable, "-c", IMPORTER, str(tmp_path / "maps"),
                               str(DEMO_MAP), "15"], stderr=subprocess.PIPE, text=True)
             for _ in range(4)]
    try:
        errors = [p.communicate(timeout=120)[1] for p in procs]
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.wait()
    assert [p.returncode for p in procs] == [0] * 4, errors
    assert MapStore(tmp_path / "maps").load("office").width > 0
    assert not list((tmp_path / "maps").rglob("*.tmp"))
