"""Opening bags: a directory of ``.mcap`` files (split bags) or one file; clear errors for
missing, truncated or corrupt files."""

from __future__ import annotations

import heapq
import os
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from mcap.exceptions import McapError
from mcap.reader import SeekingReader
from mcap.records import Channel, Schema
from mcap.summary import Summary

from .records import BagError, BagMessage
from .writer import MAGIC

__all__ = ["BagError", "BagMessage", "bag_files", "bag_span", "bags_home", "iter_messages",
           "open_summary", "resolve_bag"]


def bags_home() -> Path:
    """``$ZENROS_HOME/bags`` (``~/.zenros/bags`` by default)."""
    return Path(os.environ.get("ZENROS_HOME") or Path.home() / ".zenros").expanduser() / "bags"


def resolve_bag(name: str) -> Path:
    """A bag given on the command line: a path if it exists, else a name under `bags_home`."""
    p = Path(name).expanduser()
    if p.exists():
        return p
    home = bags_home() / name
    if home.exists():
        return home
    raise BagError(f"no bag {name!r} (looked at {p} and {home})")


def _split_index(p: Path) -> tuple[int, str]:
    m = re.search(r"_(\d+)\.mcap$", p.name)
    return (int(m.group(1)) if m else 0, p.name)


def bag_files(path: Path) -> list[Path]:
    """The files of a bag, in recording order: zenros's MCAP files, or the storage files of a
    bag recorded with ROS (a rosbag2 directory's ``.db3`` or ``.mcap`` files, ``.bag`` files:
    `zenros.bag.foreign`)."""
    if path.is_dir():
        from .foreign import foreign_files

        foreign = foreign_files(path)
        if foreign:
            return foreign
        files = sorted(path.glob("*.mcap"), key=_split_index)
        if not files:
            raise BagError(f"{path} holds no .mcap files (nor a rosbag2 bag or ROS 1 .bag files)")
        return files
    if not path.exists():
        raise BagError(f"no such bag: {path}")
    return [path]


def open_summary(path: Path) -> Summary:
    """The summary section of one file; `BagError` if it has none (a crashed recording) or
    is not MCAP at all."""
    try:
        with open(path, "rb") as f:
            head = f.read(8)
            if head != MAGIC:
                raise BagError(f"{path} is not an MCAP file (it does not start with the MCAP magic)")
            f.seek(0, os.SEEK_END)
            if f.tell() < 16 or (f.seek(-8, os.SEEK_END), f.read(8))[1] != MAGIC:
                raise BagError(f"{path} ends without its footer: the recording did not finish "
                               f"(recorder killed?) or the file was cut; run: zenros bag recover "
                               f"{path}")
            f.seek(0)
            summary = SeekingReader(f).get_summary()
    except BagError:
        raise
    except (McapError, ValueError, OSError, EOFError, KeyError) as exc:
        raise BagError(f"{path}: not a readable MCAP file ({exc or type(exc).__name__}); if the "
                       f"recorder was killed, run: zenros bag recover {path}") from exc
    if summary is None or summary.statistics is None:
        raise BagError(f"{path}: no summary (the recording did not finish); "
                       f"run: zenros bag recover {path}")
    return summary


def _file_messages(path: Path, topics: list[str] | None, start: int | None) -> Iterator[BagMessage]:
    try:
        with open(path, "rb") as f:
            reader = SeekingReader(f)
            for schema, channel, msg in reader.iter_messages(topics=topics, starting_at=start,
                                                             log_time_order=True):
                yield BagMessage(msg.log_time, msg.publish_time, msg.sequence, channel, schema,
                                 msg.data)
    except (McapError, ValueError, EOFError, KeyError) as exc:
        raise BagError(f"{path}: corrupt MCAP data ({exc or type(exc).__name__}); "
                       f"try: zenros bag recover {path}") from exc


def bag_span(files: list[Path]) -> tuple[int, int, list[tuple[Channel, Schema | None]]]:
    """(first message's log time, last one's, every channel with its schema) of a bag's files;
    for a bag recorded with ROS, the channels zenros plays its topics on."""
    from .foreign import foreign_span, is_foreign

    if is_foreign(files):
        return foreign_span(files)
    summaries = [open_summary(p) for p in files]
    stats = [s.statistics for s in summaries if s.statistics and s.statistics.message_count]
    channels = [(ch, s.schemas.get(ch.schema_id)) for s in summaries for ch in s.channels.values()]
    return (min((s.message_start_time for s in stats), default=0),
            max((s.message_end_time for s in stats), default=0), channels)


def iter_messages(files: list[Path], topics: list[str] | None = None,
                  start: int | None = None) -> Iterator[BagMessage]:
    """Every message of the bag's files in log-time order (files may overlap at a split); a
    bag recorded with ROS gives its messages converted to zenros's (`zenros.bag.foreign`)."""
    from .foreign import is_foreign, iter_foreign

    if is_foreign(files):
        yield from iter_foreign(files, topics, start)
        return
    streams: list[Any] = [_file_messages(p, topics, start) for p in files]
    if len(streams) == 1:
        yield from streams[0]
        return
    yield from heapq.merge(*streams, key=lambda m: m.log_time)
