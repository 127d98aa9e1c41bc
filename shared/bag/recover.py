"""Recovering a bag whose recorder died: rebuild each unfinished file from its complete
chunks."""

from __future__ import annotations

import os
import struct
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from mcap.exceptions import EndOfFile
from mcap.records import Channel, Chunk, McapRecord, Message, Schema
from mcap.stream_reader import StreamReader, breakup_chunk

from .foreign import is_foreign
from .reader import BagError, bag_files, open_summary
from .writer import ChunkBuffer, McapFile

__all__ = ["Recovered", "recover_bag", "recover_file"]

CHUNK = 1024 * 1024


@dataclass(frozen=True)
class Recovered:
    """The outcome for one file: how many messages were kept, and why reading stopped."""

    path: Path
    messages: int
    stopped: str  # "" when the whole file was read
    skipped_chunks: int = 0  # chunks whose data was damaged (CRC or decompression)
    already_valid: bool = False


def recover_file(src: Path, dst: Path, compression: str = "zstd") -> Recovered:
    """Copy every schema, channel and message of ``src`` up to the first damaged record into
    a complete MCAP file ``dst``. Raises `BagError` if ``src`` is not MCAP at all."""
    with open(src, "rb") as f:
        head = f.read(8)
    if head != b"\x89MCAP0\r\n":
        raise BagError(f"{src} is not an MCAP file (it does not start with the MCAP magic)")
    out = McapFile(dst, compression)
    chunk = ChunkBuffer()
    kept, stopped, skipped = 0, "", 0
    seen: set[int] = set()

    def records(f: BinaryIO) -> Iterator[McapRecord]:
        nonlocal skipped
        for record in StreamReader(f, skip_magic=False, emit_chunks=True).records:
            if not isinstance(record, Chunk):
                yield record
                continue
            try:
                inner = breakup_chunk(record, validate_crc=True)
            except Exception:  # noqa: BLE001 (damaged chunk data: skip it, keep reading)
                skipped += 1
                continue
            yield from inner

    try:
        with open(src, "rb") as f:
            for record in records(f):
                if isinstance(record, Schema):
                    out.add_schema(record.id, record.name, record.encoding, record.data)
                elif isinstance(record, Channel):
                    out.add_channel(record.id, record.topic, record.message_encoding,
                                    record.schema_id, record.metadata)
                    seen.add(record.id)
                elif isinstance(record, Message) and record.channel_id in seen:
                    chunk.add(record.channel_id, record.sequence, record.log_time,
                              record.publish_time, record.data)
                    kept += 1
                    if len(chunk) >= CHUNK:
                        out.write_chunk(chunk)
                        chunk = ChunkBuffer()
    except (EndOfFile, struct.error):
        stopped = "the file ends before its footer (recording interrupted or file truncated)"
    except Exception as exc:  # noqa: BLE001 (any damage ends the readable part of the file)
        stopped = f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
    out.write_chunk(chunk)
    out.finish()
    return Recovered(dst, kept, stopped, skipped)


def _valid(path: Path) -> bool:
    try:
        open_summary(path)
    except BagError:
        return False
    return True


def recover_bag(path: Path, compression: str = "zstd") -> list[Recovered]:
    """Rebuild every file of a bag that has no valid summary, in place; the damaged original
    is kept next to it as ``<file>.damaged``."""
    out: list[Recovered] = []
    files = bag_files(path)
    if is_foreign(files):
        raise BagError(f"{path} was recorded with ROS: recover rebuilds zenros's MCAP bags "
                       f"only (for a rosbag2 bag, see 'ros2 bag reindex')")
    for f in files:
        if _valid(f):
            stats = open_summary(f).statistics
            out.append(Recovered(f, stats.message_count if stats else 0, "", already_valid=True))
            continue
        tmp = f.with_suffix(".mcap.recovering")
        try:
            r = recover_file(f, tmp, compression)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise
        os.replace(f, f.with_suffix(".mcap.damaged"))
        os.replace(tmp, f)
        out.append(Recovered(f, r.messages, r.stopped, r.skipped_chunks))
    return out
