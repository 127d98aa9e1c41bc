"""`McapFile`: one MCAP file written chunk by chunk, with a packed (fast) message path.

The `mcap` library's records serialize everything but messages; messages are packed
straight into a chunk buffer by `ChunkBuffer.add` (about 8x faster than ``Writer.add_message``,
which keeps the recorder's hot path short). Files open in Foxglove and the mcap CLI.
"""

from __future__ import annotations

import struct
import sys
import zlib
from array import array
from collections import defaultdict
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np
from mcap.data_stream import RecordBuilder
from mcap.opcode import Opcode
from mcap.records import (
    Channel,
    Chunk,
    ChunkIndex,
    DataEnd,
    Footer,
    Header,
    Metadata,
    MetadataIndex,
    Schema,
    Statistics,
    SummaryOffset,
)

__all__ = ["COMPRESSIONS", "HEAD_DTYPE", "MESSAGE_HEAD", "RECORD_OVERHEAD", "ChunkBuffer", "McapFile", "compress"]

MAGIC = b"\x89MCAP0\r\n"
LIBRARY = "zenros-bag"
COMPRESSIONS = ("zstd", "lz4", "none")

_MSG_HEAD = struct.Struct("<BQHIQQ")  # opcode, record length, channel, sequence, log, publish
MESSAGE_HEAD = _MSG_HEAD  # pack(5, 22 + len(data), channel, sequence, log_time, publish_time)
RECORD_OVERHEAD = _MSG_HEAD.size  # bytes of a Message record besides its data
# The fields of packed Message record heads, to read many at once.
HEAD_DTYPE = np.dtype({"names": ["length", "channel", "log_time"],
                       "formats": ["<u8", "<u2", "<u8"], "offsets": [1, 9, 15],
                       "itemsize": _MSG_HEAD.size})
_INDEX_HEAD = struct.Struct("<BQHI")  # opcode, record length, channel, records length


def compress(data: bytes, compression: str) -> tuple[str, bytes]:
    """(MCAP compression name, compressed data) of one chunk."""
    if compression == "zstd":
        import zstandard

        return "zstd", zstandard.ZstdCompressor(level=1).compress(data)
    if compression == "lz4":
        import lz4.frame

        return "lz4", lz4.frame.compress(data)
    if compression in ("none", ""):
        return "", data
    raise ValueError(f"unknown compression {compression!r}; use one of {', '.join(COMPRESSIONS)}")


class ChunkBuffer:
    """Messages packed as MCAP records, plus the per-channel index of one chunk: for each
    channel a flat array of (log time, offset) pairs, written out as its MessageIndex as is."""

    __slots__ = ("buf", "index")

    def __init__(self) -> None:
        self.buf: bytearray | bytes = bytearray()  # bytes: made by `of_records`, final
        self.index: dict[int, array[int] | np.ndarray[Any, Any]] = {}

    def add(self, channel: int, sequence: int, log_time: int, publish_time: int,
            data: bytes) -> None:
        buf = self.buf
        assert isinstance(buf, bytearray), "a chunk made by of_records is final"
        idx = self.index.get(channel)
        if idx is None:
            idx = self.index[channel] = array("Q")
        assert isinstance(idx, array), "numpy indexes come from of_records: final"
        idx.append(log_time)
        idx.append(len(buf))
        buf += _MSG_HEAD.pack(5, 22 + len(data), channel, sequence & 0xFFFFFFFF, log_time,
                              publish_time)
        buf += data

    @classmethod
    def of_records(cls, parts: list[bytes], heads: np.ndarray[Any, Any] | None = None
                   ) -> ChunkBuffer:
        """A chunk of Message records given as their parts: head (`MESSAGE_HEAD` packed),
        data, head, data... (no per-message Python work: joined, and indexed with numpy).
        ``heads``: the heads already read as `HEAD_DTYPE`, if the caller has them."""
        chunk = cls()
        if len(parts) < 2:
            return chunk
        chunk.buf = b"".join(parts)
        if heads is None:
            heads = np.frombuffer(b"".join(parts[0::2]), HEAD_DTYPE)
        records = heads["length"] + 9  # opcode and length fields, then the record
        offsets = np.cumsum(records) - records
        channels, log_times = heads["channel"], heads["log_time"]
        first = int(channels[0])
        single = bool((channels == first).all())
        for channel in [first] if single else np.unique(channels).tolist():
            pick = slice(None) if single else channels == channel
            picked = log_times[pick]
            pairs = np.empty((len(picked), 2), "<u8")
            pairs[:, 0] = picked
            pairs[:, 1] = offsets[pick]
            chunk.index[channel] = pairs.reshape(-1)
        return chunk

    def __len__(self) -> int:
        return len(self.buf)


def _index_bytes(idx: array[int] | np.ndarray[Any, Any]) -> bytes:
    if isinstance(idx, np.ndarray):
        return idx.astype("<u8", copy=False).tobytes()
    if sys.byteorder != "little":  # MCAP is little-endian
        idx = array("Q", idx)
        idx.byteswap()
    return idx.tobytes()


class McapFile:
    """Writes one MCAP file: header, schemas and channels, chunks, then the summary.

    Every chunk is flushed to the OS as soon as it is written, so a process killed with
    SIGKILL leaves all complete chunks on disk (`zenros.bag.recover` rebuilds the summary).
    """

    def __init__(self, path: Path, compression: str = "zstd", profile: str = "") -> None:
        compress(b"", compression)  # validate the name up front
        self.path = path
        self.compression = compression
        self._f: BinaryIO = open(path, "wb")  # noqa: SIM115 (closed by finish)
        self._rb = RecordBuilder()
        self._schemas: dict[int, Schema] = {}
        self._channels: dict[int, Channel] = {}
        self._chunk_indexes: list[ChunkIndex] = []
        self._metadata_indexes: list[MetadataIndex] = []
        self._counts: dict[int, int] = defaultdict(int)
        self._start = 0
        self._end = 0
        self._messages = 0
        self._f.write(MAGIC)
        Header(profile=profile, library=LIBRARY).write(self._rb)
        self._emit()
        self.closed = False

    @property
    def size(self) -> int:
        """Bytes written so far."""
        return self._f.tell()

    @property
    def message_count(self) -> int:
        return self._messages

    def _emit(self) -> None:
        self._f.write(self._rb.end())  # type: ignore[no-untyped-call]  # mcap leaves it untyped

    def add_schema(self, schema_id: int, name: str, encoding: str, data: bytes) -> None:
        if schema_id in self._schemas or schema_id == 0:
            return
        s = self._schemas[schema_id] = Schema(id=schema_id, name=name, encoding=encoding, data=data)
        s.write(self._rb)
        self._emit()

    def add_channel(self, channel_id: int, topic: str, message_encoding: str, schema_id: int,
                    metadata: dict[str, str] | None = None) -> None:
        if channel_id in self._channels:
            return
        c = self._channels[channel_id] = Channel(
            id=channel_id, topic=topic, message_encoding=message_encoding, schema_id=schema_id,
            metadata=dict(metadata or {}),
        )
        c.write(self._rb)
        self._emit()

    def add_metadata(self, name: str, data: dict[str, str]) -> None:
        offset = self._f.tell()
        Metadata(name=name, metadata=data).write(self._rb)
        self._metadata_indexes.append(MetadataIndex(offset=offset, length=self._rb.count,
                                                    name=name))
        self._emit()

    def write_chunk(self, chunk: ChunkBuffer) -> None:
        """Compress and append one chunk and its message indexes, then flush to the OS."""
        if not chunk.index:
            return
        raw = bytes(chunk.buf)
        start = min(int(np.frombuffer(i, np.uint64)[0::2].min()) for i in chunk.index.values())
        end = max(int(np.frombuffer(i, np.uint64)[0::2].max()) for i in chunk.index.values())
        name, data = compress(raw, self.compression)
        offset = self._f.tell()
        Chunk(compression=name, data=data, message_start_time=start, message_end_time=end,
              uncompressed_crc=zlib.crc32(raw), uncompressed_size=len(raw)).write(self._rb)
        chunk_length = self._rb.count
        self._emit()
        index_start = self._f.tell()
        offsets: dict[int, int] = {}
        for channel, idx in chunk.index.items():
            offsets[channel] = index_start + self._rb.count
            body = _index_bytes(idx)
            self._rb.write(_INDEX_HEAD.pack(Opcode.MESSAGE_INDEX, 6 + len(body), channel,
                                            len(body)))
            self._rb.write(body)
            self._counts[channel] += len(idx) // 2
            self._messages += len(idx) // 2
        index_length = self._rb.count
        self._emit()
        self._chunk_indexes.append(ChunkIndex(
            message_start_time=start, message_end_time=end, chunk_start_offset=offset,
            chunk_length=chunk_length, message_index_offsets=offsets,
            message_index_length=index_length, compression=name, compressed_size=len(data),
            uncompressed_size=len(raw),
        ))
        self._start = start if len(self._chunk_indexes) == 1 else min(self._start, start)
        self._end = max(self._end, end)
        self._f.flush()

    def finish(self) -> None:
        """Write the summary and footer and close the file."""
        if self.closed:
            return
        self.closed = True
        DataEnd(data_section_crc=0).write(self._rb)
        self._emit()
        summary_start = self._f.tell()
        rb = RecordBuilder()
        offsets: list[SummaryOffset] = []

        def group(opcode: Opcode, records: list[object]) -> None:
            begin = rb.count
            for r in records:
                r.write(rb)  # type: ignore[attr-defined]
            if rb.count > begin:
                offsets.append(SummaryOffset(group_opcode=opcode, group_start=summary_start + begin,
                                             group_length=rb.count - begin))

        group(Opcode.SCHEMA, list(self._schemas.values()))
        group(Opcode.CHANNEL, list(self._channels.values()))
        group(Opcode.STATISTICS, [Statistics(
            message_count=self._messages, schema_count=len(self._schemas),
            channel_count=len(self._channels), attachment_count=0,
            metadata_count=len(self._metadata_indexes), chunk_count=len(self._chunk_indexes),
            message_start_time=self._start, message_end_time=self._end,
            channel_message_counts=dict(self._counts),
        )])
        group(Opcode.CHUNK_INDEX, list(self._chunk_indexes))
        group(Opcode.METADATA_INDEX, list(self._metadata_indexes))
        offset_start = summary_start + rb.count
        for o in offsets:
            o.write(rb)
        summary = rb.end()  # type: ignore[no-untyped-call]
        crc = zlib.crc32(summary)
        crc = zlib.crc32(struct.pack("<BQQQ", Opcode.FOOTER, 20, summary_start, offset_start), crc)
        self._f.write(summary)
        Footer(summary_start=summary_start, summary_offset_start=offset_start,
               summary_crc=crc).write(self._rb)
        self._emit()
        self._f.write(MAGIC)
        self._f.close()

    def abandon(self) -> None:
        """Close without a summary (what a crash leaves; for tests of recovery)."""
        if not self.closed:
            self.closed = True
            self._f.close()
