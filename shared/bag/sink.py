"""`BagSink`: thread-safe message intake in batches; a writer thread packs, compresses,
writes and splits files."""

from __future__ import annotations

import queue
import threading
from dataclasses import dataclass
from itertools import chain
from pathlib import Path
from typing import Any

import numpy as np

from .writer import HEAD_DTYPE, MESSAGE_HEAD, ChunkBuffer, McapFile, compress

__all__ = ["CHUNK_SIZE", "FLUSH_INTERVAL", "BagSink", "ChannelInfo", "SplitPolicy"]

CHUNK_SIZE = 1024 * 1024  # bytes of messages per chunk (before compression)
FLUSH_INTERVAL = 1.0  # seconds: a chunk is closed and written at least this often
QUEUE_CHUNKS = 32  # chunks waiting for the writer thread before `add` blocks (back-pressure)


@dataclass(frozen=True)
class SplitPolicy:
    """When to start the next file: after ``max_bytes`` bytes or ``max_seconds`` of messages
    (0: never). Files split at chunk boundaries."""

    max_bytes: int = 0
    max_seconds: float = 0.0


@dataclass(frozen=True)
class ChannelInfo:
    """A channel as every file of the bag declares it."""

    id: int
    topic: str
    message_encoding: str
    schema_id: int
    schema_name: str
    schema_encoding: str
    schema_data: bytes
    metadata: dict[str, str]


class BagSink:
    """Takes messages from any thread; writes ``<directory>/<name>_<i>.mcap`` files.

    `add_batch` appends a list of packed Message records to the open chunk under a lock
    (one lock and a size count per batch). A full chunk, or one open for `FLUSH_INTERVAL`,
    goes to the writer thread, which joins and indexes it, compresses it, appends it and
    flushes it to the OS. So a recorder killed with SIGKILL loses at most the
    open chunk: `CHUNK_SIZE` bytes or `FLUSH_INTERVAL` seconds of messages, whichever is less
    (plus the few chunks queued for the writer thread if the disk is slower than the input).
    """

    def __init__(self, directory: Path, name: str, *, compression: str = "zstd",
                 chunk_size: int = CHUNK_SIZE, flush_interval: float = FLUSH_INTERVAL,
                 split: SplitPolicy | None = None) -> None:
        compress(b"", compression)  # an unknown name fails here, before any file exists
        self.directory = directory
        self.name = name
        self.compression = compression
        self.chunk_size = chunk_size
        self.flush_interval = flush_interval
        self.split = split or SplitPolicy()
        self.files: list[Path] = []
        self.channels: dict[int, ChannelInfo] = {}
        self.counts: dict[int, int] = {}
        self._schemas: dict[tuple[str, str, bytes], int] = {}
        self._seq: dict[int, int] = {}  # channel -> last sequence number given by `add`
        self._count = 0  # messages taken
        self._lock = threading.Lock()
        self._open: list[list[bytes]] = []  # the open chunk's batches of record parts
        self._open_bytes = 0
        self._queue: queue.Queue[Any] = queue.Queue(QUEUE_CHUNKS)
        self._file_start = -1
        self._error: BaseException | None = None
        directory.mkdir(parents=True, exist_ok=True)
        self._file: McapFile | None = self._open_file()
        self._stop = threading.Event()
        self._writer = threading.Thread(target=self._write_loop, name="zenros-bag-writer",
                                        daemon=True)
        self._ticker = threading.Thread(target=self._tick_loop, name="zenros-bag-flush",
                                        daemon=True)
        self._writer.start()
        self._ticker.start()

    # ------------------------------------------------------------------ intake

    def add_channel(self, topic: str, message_encoding: str, schema_name: str,
                    schema_encoding: str, schema_data: bytes,
                    metadata: dict[str, str] | None = None) -> int:
        """Declare a channel (in every file from now on); returns its id."""
        with self._lock:
            key = (schema_name, schema_encoding, schema_data)
            schema_id = 0
            if schema_encoding:
                schema_id = self._schemas.setdefault(key, len(self._schemas) + 1)
            info = ChannelInfo(len(self.channels) + 1, topic, message_encoding, schema_id,
                               schema_name, schema_encoding, schema_data, dict(metadata or {}))
            self.channels[info.id] = info
            self.counts[info.id] = 0
            self._queue.put(("channel", info))
            return info.id

    def add(self, channel: int, log_time: int, publish_time: int, data: bytes) -> None:
        """Append one message, numbered after the last one `add` gave ``channel``."""
        with self._lock:
            seq = self._seq[channel] = self._seq.get(channel, 0) + 1
        self.add_batch([MESSAGE_HEAD.pack(5, 22 + len(data), channel, seq & 0xFFFFFFFF,
                                          log_time, publish_time), data])

    def add_batch(self, parts: list[bytes], size: int = -1) -> None:
        """Append Message records given as their parts, in order: head (`MESSAGE_HEAD`
        packed: channel, sequence, log and publish time), data, head, data... (the hot path:
        one lock per batch). Whoever packs a channel's heads numbers its messages. The list
        is the sink's from now on. ``size``: its bytes, if the caller counted them."""
        if size < 0:
            size = sum(map(len, parts))
        with self._lock:
            self._open.append(parts)
            self._count += len(parts) // 2
            self._open_bytes += size
            if self._open_bytes >= self.chunk_size:
                self._hand_over()

    def _hand_over(self) -> None:
        """Send the open chunk to the writer thread (called with the lock held)."""
        if self._open:
            batches, self._open, self._open_bytes = self._open, [], 0
            self._queue.put(("chunk", batches))

    def flush(self) -> None:
        """Close the open chunk now (it is written shortly after)."""
        with self._lock:
            self._hand_over()

    @property
    def message_count(self) -> int:
        """Messages taken so far (written, or on their way to disk)."""
        return self._count

    # ------------------------------------------------------------------ writer thread

    def _open_file(self) -> McapFile:
        path = self.directory / f"{self.name}_{len(self.files)}.mcap"
        f = McapFile(path, self.compression)
        self.files.append(path)
        self._file_start = -1
        return f

    def _declare(self, f: McapFile, info: ChannelInfo) -> None:
        if info.schema_id:
            f.add_schema(info.schema_id, info.schema_name, info.schema_encoding, info.schema_data)
        f.add_channel(info.id, info.topic, info.message_encoding, info.schema_id, info.metadata)

    def _write_loop(self) -> None:
        try:
            while True:
                kind, item = self._queue.get()
                if kind == "stop":
                    if self._file is not None:
                        self._file.finish()
                    return
                if kind == "channel":
                    if self._file is not None:  # else the next file declares it
                        self._declare(self._file, item)
                    continue
                self._write_batches(item)
        except BaseException as exc:  # noqa: BLE001 (reported by close(); the disk may be full)
            self._error = exc
            while True:  # keep draining so producers never block forever
                if self._queue.get()[0] == "stop":
                    return

    def _write_batches(self, batches: list[list[bytes]]) -> None:
        """Write batches of record parts as chunks of `chunk_size` bytes (the last one may be
        smaller; a chunk closes with the record that fills it)."""
        parts = list(chain.from_iterable(batches))
        heads = np.frombuffer(b"".join(parts[0::2]), HEAD_DTYPE)
        ends = np.cumsum(heads["length"] + 9)  # where each record ends
        start, n = 0, len(ends)
        while start < n:
            base = int(ends[start - 1]) if start else 0
            stop = min(n, int(np.searchsorted(ends, base + self.chunk_size)) + 1)
            self._write_chunk(ChunkBuffer.of_records(parts[2 * start:2 * stop],
                                                     heads[start:stop]))
            start = stop

    def _write_chunk(self, chunk: ChunkBuffer) -> None:
        if self._file is None:  # split: the next file opens with its first chunk
            self._file = self._open_file()
            for info in list(self.channels.values()):
                self._declare(self._file, info)
        f = self._file
        first = min(int(idx[0]) for idx in chunk.index.values())
        if self._file_start < 0:
            self._file_start = first
        f.write_chunk(chunk)
        for channel, idx in chunk.index.items():
            self.counts[channel] = self.counts.get(channel, 0) + len(idx) // 2
        last = max(int(idx[-2]) for idx in chunk.index.values())
        split = self.split
        if ((split.max_bytes and f.size >= split.max_bytes)
                or (split.max_seconds and last - self._file_start >= split.max_seconds * 1e9)):
            f.finish()
            self._file = None

    def _tick_loop(self) -> None:
        while not self._stop.wait(self.flush_interval):
            self.flush()

    # ------------------------------------------------------------------ end

    def close(self) -> None:
        """Write what is left, finish the last file (summary and footer) and stop."""
        if self._stop.is_set():
            return
        self._stop.set()
        self._ticker.join()
        with self._lock:
            self._hand_over()
            self._queue.put(("stop", None))
        self._writer.join()
        if self._error is not None:
            raise OSError(f"writing {self.files[-1]} failed: {self._error}") from self._error
