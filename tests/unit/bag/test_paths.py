"""Where bags go and how names given on the command line are found."""

from __future__ import annotations

from pathlib import Path

import pytest
from zenros.bag import BagError, bags_home, resolve_bag
from zenros.cli.bag import output_dir


@pytest.fixture
def home(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("ZENROS_HOME", str(tmp_path / "zh"))
    return tmp_path / "zh" / "bags"


def test_plain_names_go_under_zenros_home(home: Path) -> None:
    assert bags_home() == home
    assert output_dir("run1") == home / "run1"
    assert output_dir(None).parent == home
    assert output_dir(None).name.startswith("zenros_bag_")


def test_paths_are_used_as_given(home: Path, tmp_path: Path) -> None:
    assert output_dir(str(tmp_path / "x")) == tmp_path / "x"
    assert output_dir(str(tmp_path / "y.mcap")) == tmp_path / "y"


def test_existing_bag_is_refused(home: Path) -> None:
    (home / "taken").mkdir(parents=True)
    (home / "taken" / "taken_0.mcap").write_bytes(b"")
    with pytest.raises(BagError, match="already exists"):
        output_dir("taken")
    (home / "empty").mkdir()
    assert output_dir("empty") == home / "empty"  # an empty directory is fine


def test_resolve_bag(home: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (home / "run").mkdir(parents=True)
    monkeypatch.chdir(tmp_path)
    assert resolve_bag("run") == home / "run"
    (tmp_path / "local").mkdir()
    assert resolve_bag("local") == Path("local")
    with pytest.raises(BagError, match="no bag 'nope'"):
        resolve_bag("nope")
