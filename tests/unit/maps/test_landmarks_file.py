"""zenros.maps.landmarks: landmarks.yaml round trip, the demo office's reflectors, clear
errors."""

from __future__ import annotations

from pathlib import Path

import pytest
from zenros.errors import MapError
from zenros.maps import Reflector, landmarks_path, load_landmarks, load_map, save_landmarks

OFFICE = Path(__file__).parents[3] / "deploy" / "maps" / "office" / "office.yaml"


def test_round_trip_and_no_file(tmp_path: Path) -> None:
    y = tmp_path / "m.yaml"
    assert load_landmarks(y) == []
    marks = [Reflector("a", 1.0, 2.0), Reflector("b", -3.5, 0.25, 0.03)]
    assert save_landmarks(marks, y) == landmarks_path(tmp_path) == tmp_path / "landmarks.yaml"
    assert load_landmarks(y) == marks and load_landmarks(tmp_path) == marks


@pytest.mark.parametrize(("text", "match"), [
    ("[1, 2]", "expected a mapping with 'reflectors'"),
    ("reflectors: {a: 1}", "'reflectors' must be a list"),
    ("walls: []", r"unknown keys \['walls'\]"),
    ("reflectors: [{id: a, x: 1}]", r"reflectors\[0\] must be a mapping with id, x, y"),
    ("reflectors: [{id: a, x: 1, y: .nan}]", r"reflectors\[0\].y must be a finite number"),
    ("reflectors: [{id: a, x: 1, y: 2, r: 1}]", r"unknown keys \['r'\]"),
    ("reflectors: [{id: '', x: 1, y: 2}]", r"reflectors\[0\].id must be a non-empty string"),
    ("reflectors: [{id: a, x: 1, y: 2, radius: 0}]", r"radius must be in \(0, 0.5\]"),
    ("reflectors: [{id: a, x: 1, y: 2}, {id: a, x: 3, y: 4}]", "'a' is used twice"),
    ("reflectors: [{id: a, x: 1, y: 2", "cannot read landmarks"),
])
def test_malformed_files_name_the_file_and_the_entry(tmp_path: Path, text: str,
                                                      match: str) -> None:
    (tmp_path / "landmarks.yaml").write_text(text)
    with pytest.raises(MapError, match=match) as err:
        load_landmarks(tmp_path / "m.yaml")
    assert "landmarks.yaml" in str(err.value)


def test_an_integer_id_is_its_digits(tmp_path: Path) -> None:
    (tmp_path / "landmarks.yaml").write_text("reflectors: [{id: 7, x: 1, y: 2}]\n")
    assert load_landmarks(tmp_path) == [Reflector("7", 1.0, 2.0)]


def test_the_office_reflectors_sit_on_wall_faces() -> None:
    """Each demo reflector's centre is on a free cell's edge next to a solid one."""
    marks = load_landmarks(OFFICE)
    assert len(marks) >= 12 and len({m.id for m in marks}) == len(marks)
    grid = load_map(OFFICE)
    for m in marks:
        cells = set()
        for dx, dy in ((0.02, 0), (-0.02, 0), (0, 0.02), (0, -0.02)):
            col = int((m.x + dx - grid.origin[0]) / grid.resolution)
            row = int((m.y + dy - grid.origin[1]) / grid.resolution)
            cells.add(int(grid.grid[row, col]) >= 50)
        assert cells == {True, False}, m
