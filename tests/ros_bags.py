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


def to_rosbag2(src: Path, out: Path, storage: str = "sqlite3") -> Path:
    """A zenros bag re-written as ``ros2 bag record`` would have stored the same messages
    (``make_ros_bag.py --from``)."""
    path: Path = script().from_zenros_bag(src, out, storage)
    return path


def to_zenros_bag(src: Path, out: Path) -> Path:
    """The messages of any bag zenros reads (one recorded with ROS too), as they come out of
    `zenros.bag.iter_messages`, written as a zenros MCAP file (``out``)."""
    from zenros.bag import bag_files, iter_messages
    from zenros.bag.writer import ChunkBuffer, McapFile

    f = McapFile(out, "zstd")
    schemas: dict[str, int] = {}
    channels: dict[tuple[str, str], int] = {}
    chunk = ChunkBuffer()
    for m in iter_messages(bag_files(src)):
        key = (m.channel.topic, m.channel.metadata["zenoh_encoding"])
        if key not in channels:
            sid = 0
            if m.schema is not None:
                if m.schema.name not in schemas:
                    schemas[m.schema.name] = len(schemas) + 1
                    f.add_schema(schemas[m.schema.name], m.schema.name, m.schema.encoding,
                                 m.schema.data)
                sid = schemas[m.schema.name]
            channels[key] = len(channels) + 1
            f.add_channel(channels[key], m.channel.topic, m.channel.message_encoding, sid,
                          dict(m.channel.metadata))
        chunk.add(channels[key], m.sequence + 1, m.log_time, m.publish_time, m.data)
    f.write_chunk(chunk)
    f.finish()
    return out
