"""Where bags go and how names given on the command line are found."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from zenros.bag import BagError, bags_home, resolve_bag
from zenros.cli.bag import output_dir


@pytest.fixture
def home(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("ZENROS_HOME", str(tmp_path / "zh"))
    return tmp_path / "zh" / "bags"


def test_names_are_relative_to_the_working_directory_as_ros2_bag_has_them(
        home: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``-o first_drive`` is ./first_drive, as ``ros2 bag record -o`` (issue 37.10)."""
    monkeypatch.chdir(tmp_path)
    assert bags_home() == home
    assert output_dir("run1") == tmp_path / "run1"
    assert output_dir("sub/run2") == tmp_path / "sub" / "run2"
    dated = output_dir(None)
    assert dated.parent == tmp_path
    assert re.fullmatch(r"rosbag2_\d{4}_\d\d_\d\d-\d\d_\d\d_\d\d", dated.name), dated.name


def test_paths_are_used_as_given(home: Path, tmp_path: Path) -> None:
    assert output_dir(str(tmp_path / "x")) == tmp_path / "x"
    assert output_dir(str(tmp_path / "y.mcap")) == tmp_path / "y"


def test_an_existing_directory_is_refused_as_ros2_bag_does(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "taken_0.mcap").write_bytes(b"")
    with pytest.raises(BagError, match="output folder 'taken' already exists"):
        output_dir("taken")
    (tmp_path / "empty").mkdir()
    with pytest.raises(BagError, match="already exists"):
        output_dir("empty")


def test_resolve_bag(home: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (home / "run").mkdir(parents=True)
    monkeypatch.chdir(tmp_path)
    assert resolve_bag("run") == home / "run"
    (tmp_path / "local").mkdir()
    assert resolve_bag("local") == Path("local")
    with pytest.raises(BagError, match="no bag 'nope'"):
        resolve_bag("nope")
