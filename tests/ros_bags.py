"""Bags as ROS records them, for the tests of `zenros.bag.foreign`: written by
``scripts/make_ros_bag.py`` (rosbags' own writers), and the values zenros must read back.

``tests/`` is on ``sys.path`` (its conftest.py), so a test imports this as ``ros_bags``.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "make_ros_bag.py"
STORAGES = ("sqlite3", "mcap", "ros1")


def script() -> ModuleType:
    """scripts/make_ros_bag.py as a module (it needs rosbags: skip the test without it)."""
    spec = importlib.util.spec_from_file_location("make_ros_bag", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def make(directory: Path, storage: str, n: int = 10, unknown: bool = False) -> Path:
    """A bag of ``storage`` under ``directory``: a rosbag2 directory or a ROS 1 .bag file."""
    out = directory / (f"{storage}.bag" if storage == "ros1" else storage)
    script().write_bag(out, storage, n, unknown)
    return out
