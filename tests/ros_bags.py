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
    """A zenros bag re-written as ``ros2 bag record`` would have stored the same messages: a
    rosbag2 directory (``storage`` sqlite3 or mcap), each message CDR-encoded by zenros's
    codec under its ROS 2 name, at the same log times, in the same order (the standard
    types only: rosbags' Kilted store defines the connections)."""
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    from zenros.bag import bag_files, iter_messages
    from zenros.codec import decode_any
    from zenros.qos import QoSProfile, Reliability
    from zenros.ros2 import cdr_codec, ros_name_of

    store = get_typestore(Stores.ROS2_KILTED)
    never = QosTime(sec=0, nsec=0)
    plugin = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}[storage]
    with Writer(out, version=9, storage_plugin=plugin) as w:
        conns: dict[tuple[str, str], object] = {}
        for m in iter_messages(bag_files(src)):
            msg = decode_any(m.data, m.channel.metadata["zenoh_encoding"])
            name = ros_name_of(type(msg))
            key = (m.channel.topic, name)
            if key not in conns:
                q = QoSProfile.from_tag(m.channel.metadata.get("qos", "rel+10"))
                qos = Qos(QosHistory.KEEP_LAST, q.depth,
                          QosReliability.RELIABLE if q.reliability == Reliability.RELIABLE
                          else QosReliability.BEST_EFFORT,
                          QosDurability.TRANSIENT_LOCAL if q.latched else QosDurability.VOLATILE,
                          never, never, QosLiveliness.AUTOMATIC, never, False)
                conns[key] = w.add_connection(m.channel.topic, name, typestore=store,
                                              offered_qos_profiles=[qos])
            w.write(conns[key], m.log_time, cdr_codec(type(msg)).encode(msg))  # type: ignore[arg-type]
    return out


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
