"""zenros.maps: map_server semantics (Part D1 table), round trips, poses, clear errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from zenros.errors import MapError
from zenros.maps import (
    GridMap,
    MapPose,
    MapPoses,
    load_map,
    load_poses,
    pixels_to_grid,
    read_image,
    save_map,
    save_poses,
)
from zenros.msgs.nav_msgs import OccupancyGrid

OFFICE = Path(__file__).parents[3] / "deploy" / "maps" / "office" / "office.yaml"
PIXELS = np.array([[0, 100, 205], [254, 255, 128]], np.uint8)  # top row first


def write_map(tmp: Path, *, mode: str = "trinary", negate: int = 0, extra: str = "") -> Path:
    (tmp / "m.pgm").write_bytes(b"P5\n# a comment\n3 2\n255\n" + PIXELS.tobytes())
    y = tmp / "m.yaml"
    y.write_text(f"image: m.pgm\nresolution: 0.05\norigin: [-1.0, -2.0, 0.0]\nnegate: {negate}\n"
                 f"occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: {mode}\n{extra}")
    return y


@pytest.mark.parametrize(("mode", "top", "bottom"), [
    ("trinary", [100, -1, -1], [0, 0, -1]),
    ("scale", [100, 91, 0], [0, 0, 67]),
    ("raw", [0, 100, -1], [-1, -1, -1]),
])
def test_modes_match_the_spec_table(tmp_path: Path, mode: str, top: list[int],
                                    bottom: list[int]) -> None:
    m = load_map(write_map(tmp_path, mode=mode))
    # rows flipped: grid row 0 is the image's bottom row
    assert m.grid[1].tolist() == top
    assert m.grid[0].tolist() == bottom
    assert m.origin == (-1.0, -2.0, 0.0) and m.resolution == 0.05


def test_negate_swaps_black_and_white(tmp_path: Path) -> None:
    m = load_map(write_map(tmp_path, negate=1))
    assert m.grid[1, 0] == 0 and m.grid[0, 1] == 100


def test_alpha_below_255_is_unknown() -> None:
    px = np.array([[[0, 255], [0, 10]]], np.uint8)
    assert pixels_to_grid(px).tolist() == [[100, -1]]


@pytest.mark.parametrize("fmt", ["pgm", "png"])
def test_trinary_round_trip_is_exact(tmp_path: Path, fmt: str) -> None:
    grid = np.array([[0, 100, -1, 0], [-1, -1, 100, 0]], np.int8)
    src = GridMap(grid, 0.1, (1.5, -2.25, 0.0))
    image = save_map(src, tmp_path / "a.yaml", image_format=fmt)
    assert image.suffix == "." + fmt
    back = load_map(tmp_path / "a.yaml")
    assert np.array_equal(back.grid, grid) and back == src


def test_scale_round_trip_within_one(tmp_path: Path) -> None:
    grid = np.array([[0, 30, 60, 100, -1]], np.int8)
    save_map(GridMap(grid, 0.05), tmp_path / "s.yaml", mode="scale", image_format="png")
    back = load_map(tmp_path / "s.yaml").grid
    assert back[0, 4] == -1 and back[0, 0] == 0 and back[0, 3] == 100
    assert np.all(np.abs(back[0, 1:3].astype(int) - [30, 60]) <= 1)


def test_occupancy_grid_round_trip_and_cells() -> None:
    grid = np.arange(12, dtype=np.int8).reshape(3, 4)
    m = GridMap(grid, 0.5, (-1.0, 2.0, math.pi / 2))
    msg = m.to_msg()
    assert isinstance(msg, OccupancyGrid) and msg.info.width == 4 and msg.info.height == 3
    assert msg.grid()[2, 3] == 11
    back = GridMap.from_msg(msg)
    assert np.array_equal(back.grid, grid) and back.origin[2] == pytest.approx(math.pi / 2)
    plain = GridMap(grid, 0.5, (-1.0, 2.0, 0.0))
    assert plain.world_to_cell(-0.9, 2.6) == (1, 0)
    assert plain.cell_to_world(1, 0) == (-0.75, 2.75)
    x, y = m.cell_to_world(0, 1)
    assert m.world_to_cell(x, y) == (0, 1)


def test_bad_occupancy_grid() -> None:
    msg = GridMap(np.zeros((2, 2), np.int8), 0.1).to_msg()
    msg.info.width = 3
    with pytest.raises(MapError, match="3x2 cells but 4 values"):
        GridMap.from_msg(msg)


@pytest.mark.parametrize(("extra", "yaml_text", "match"), [
    (None, "image: m.pgm\n", "missing required key 'resolution'"),
    (None, "{bad yaml", "not valid YAML"),
    (None, "- a list", "expected a mapping"),
    ("thresh", "", "'free_thresh' \\(0.7\\) must be below 'occupied_thresh'"),
    ("origin", "", "'origin' must be a list of 3 numbers"),
    ("mode", "", "'mode' must be one of trinary, scale, raw"),
    ("image", "", "'image' names .*nothere.pgm.*does not exist"),
    ("res", "", "'resolution' must be a positive number"),
])
def test_bad_yaml_names_file_and_field(tmp_path: Path, extra: str | None, yaml_text: str,
                                       match: str) -> None:
    y = write_map(tmp_path)
    fields = {"image": "m.pgm", "resolution": "0.05", "origin": "[0, 0, 0]", "negate": "0",
              "occupied_thresh": "0.65", "free_thresh": "0.196", "mode": "trinary"}
    if extra is None:
        y.write_text(yaml_text)
    else:
        fields.update({"thresh": {"free_thresh": "0.7"}, "origin": {"origin": "[0, 0]"},
                       "mode": {"mode": "fancy"}, "image": {"image": "nothere.pgm"},
                       "res": {"resolution": "-1"}}[extra])
        y.write_text("".join(f"{k}: {v}\n" for k, v in fields.items()))
    with pytest.raises(MapError, match=match) as err:
        load_map(y)
    assert str(y) in str(err.value)


def test_missing_yaml_and_bad_image(tmp_path: Path) -> None:
    with pytest.raises(MapError, match="cannot read map YAML"):
        load_map(tmp_path / "none.yaml")
    y = write_map(tmp_path)
    (tmp_path / "m.pgm").write_bytes(b"P5\n3 2\n255\n\x00")
    with pytest.raises(MapError, match="m.pgm: PGM has 1 bytes of pixels, expected 6"):
        load_map(y)
    (tmp_path / "m.pgm").write_bytes(b"not an image")
    with pytest.raises(MapError, match="not a readable image"):
        read_image(tmp_path / "m.pgm")


def test_ascii_pgm_and_16_bit(tmp_path: Path) -> None:
    p = tmp_path / "a.pgm"
    p.write_bytes(b"P2\n2 1\n15\n0 15\n")
    assert read_image(p).tolist() == [[0, 255]]
    p.write_bytes(b"P5\n1 1\n65535\n\xff\xff")
    assert read_image(p).tolist() == [[255]]


def test_poses_round_trip_and_errors(tmp_path: Path) -> None:
    y = write_map(tmp_path)
    assert load_poses(y) == MapPoses()
    poses = MapPoses(start=MapPose(1.0, 2.0), dock=MapPose(3.0, 4.0, -1.5))
    save_poses(poses, y)
    assert load_poses(y) == poses and load_poses(tmp_path) == poses
    (tmp_path / "poses.yaml").write_text("dock: {x: 1}\n")
    with pytest.raises(MapError, match="poses.yaml: 'dock' must be a mapping with x, y"):
        load_poses(y)
    (tmp_path / "poses.yaml").write_text("home: {x: 1, y: 2}\n")
    with pytest.raises(MapError, match="unknown keys \\['home'\\]"):
        load_poses(y)
    (tmp_path / "poses.yaml").write_text("start: {x: 1, y: .nan}\n")
    with pytest.raises(MapError, match="'start.y' must be a finite number"):
        load_poses(y)


def test_demo_map_loads_with_free_start_and_dock() -> None:
    m = load_map(OFFICE)
    assert m.resolution == 0.05 and 20 <= m.width * m.resolution <= 30
    poses = load_poses(OFFICE)
    assert poses.start is not None and poses.dock is not None
    for p in (poses.start, poses.dock):
        assert m.grid[m.world_to_cell(p.x, p.y)] == 0
