"""`BagInfo`: what ``zenros bag info`` prints, like ``ros2 bag info``."""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass, field
from pathlib import Path

from .foreign import foreign_summary, is_foreign
from .reader import bag_files, open_summary

__all__ = ["BagInfo", "TopicInfo", "bag_info", "format_info"]


@dataclass
class TopicInfo:
    topic: str
    type: str
    encoding: str
    count: int = 0
    skipped: str = ""  # a topic of a ROS bag zenros does not play: why


@dataclass
class BagInfo:
    path: Path
    files: list[Path]
    size: int
    start: int
    end: int
    messages: int
    compression: list[str]
    chunks: int
    topics: list[TopicInfo] = field(default_factory=list)
    storage: str = "mcap"  # sqlite3, mcap or rosbag1 for a bag recorded with ROS
    recorded_with_ros: bool = False

    @property
    def duration(self) -> float:
        return max(0, self.end - self.start) / 1e9


def bag_info(path: Path) -> BagInfo:
    """Summaries of every file of a bag, merged; `BagError` for unreadable files."""
    files = bag_files(path)
    if is_foreign(files):
        return _ros_bag_info(path, files)
    start, end, messages, chunks = 0, 0, 0, 0
    compression: set[str] = set()
    topics: dict[tuple[str, str, str], TopicInfo] = {}
    for f in files:
        s = open_summary(f)
        st = s.statistics
        assert st is not None
        if st.message_count:
            start = st.message_start_time if not messages else min(start, st.message_start_time)
            end = max(end, st.message_end_time)
        messages += st.message_count
        chunks += len(s.chunk_indexes)
        compression.update(c.compression or "none" for c in s.chunk_indexes)
        for ch in s.channels.values():
            schema = s.schemas.get(ch.schema_id)
            key = (ch.topic, schema.name if schema else "", ch.message_encoding)
            t = topics.setdefault(key, TopicInfo(*key))
            t.count += st.channel_message_counts.get(ch.id, 0)
    return BagInfo(path, files, sum(f.stat().st_size for f in files), start, end, messages,
                   sorted(compression) or ["none"], chunks,
                   sorted(topics.values(), key=lambda t: t.topic))


def _ros_bag_info(path: Path, files: list[Path]) -> BagInfo:
    """A bag recorded with ROS: its own types and encodings, and the topics zenros skips."""
    s = foreign_summary(files)
    topics = [TopicInfo(t.topic, t.ros_type, t.encoding, t.count, t.skipped) for t in s.topics]
    return BagInfo(path, files, sum(f.stat().st_size for f in files), s.start, s.end, s.messages,
                   [s.compression or "none"], 0, topics, s.storage, True)


def _size(n: float) -> str:
    for unit in ("B", "KiB", "MiB", "GiB"):
        if n < 1024:
            return f"{n:.1f} {unit}"
        n /= 1024
    return f"{n:.1f} TiB"


def _stamp(ns: int) -> str:
    t = dt.datetime.fromtimestamp(ns / 1e9, tz=dt.UTC)
    return f"{t:%b %d %Y %H:%M:%S.%f}"[:-3] + f" UTC ({ns // 10**9}.{ns % 10**9:09d})"


def format_info(info: BagInfo) -> str:
    """The ``ros2 bag info`` layout."""
    width = max((len(t.topic) for t in info.topics), default=0)
    lines = [
        f"Files:             {', '.join(f.name for f in info.files)}",
        f"Bag size:          {_size(info.size)}",
        f"Storage id:        {info.storage}" + (" (recorded with ROS)"
                                                   if info.recorded_with_ros else ""),
        (f"Compression:       {', '.join(info.compression)} ({info.chunks} chunks)"
         if not info.recorded_with_ros else f"Compression:       {info.compression[0]}"),
        f"Duration:          {info.duration:.3f}s",
        f"Start:             {_stamp(info.start)}" if info.messages else "Start:             -",
        f"End:               {_stamp(info.end)}" if info.messages else "End:               -",
        f"Messages:          {info.messages}",
    ]
    for i, t in enumerate(info.topics):
        rate = t.count / info.duration if info.duration > 0 else 0.0
        head = "Topic information: " if i == 0 else " " * 19
        lines.append(f"{head}Topic: {t.topic:<{width}} | Type: {t.type or '-'} | "
                     f"Count: {t.count} | Rate: {rate:.2f} Hz | "
                     f"Serialization Format: {t.encoding}"
                     + (f" | NOT PLAYED: {t.skipped}" if t.skipped else ""))
    if not info.topics:
        lines.append("Topic information:")
    return "\n".join(lines)
