"""`OutputBag`: a deterministic run's outputs written as one MCAP file, in the format of
``zenros bag record`` (same channels' metadata, schemas and encodings), with log time the
simulated time, so the same run writes the same bytes."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..bag.schema import message_encoding, schema_for
from ..bag.writer import ChunkBuffer, McapFile
from ..codec import codec_for

__all__ = ["OutputBag"]

CHUNK_BYTES = 1024 * 1024  # a chunk closes at this many bytes of messages, never on a timer


class OutputBag:
    """Writes messages as they come (`add`), in one thread, chunked by size only: nothing
    about the file depends on the wall clock or on thread timing."""

    def __init__(self, path: Path, compression: str = "zstd") -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        self._file = McapFile(path, compression)
        self._chunk = ChunkBuffer()
        self._bytes = 0
        self._channels: dict[tuple[str, str], int] = {}
        self._schemas: dict[str, int] = {}
        self._seq: dict[int, int] = {}
        self.count = 0

    def _channel(self, topic: str, msg: Any, qos: str) -> tuple[int, Any]:
        codec = codec_for(type(msg))
        key = (topic, codec.type_name)
        cid = self._channels.get(key)
        if cid is None:
            cid = self._channels[key] = len(self._channels) + 1
            schema_encoding, schema = schema_for(codec.type_name)
            sid = 0
            if schema_encoding:
                sid = self._schemas.setdefault(codec.type_name, len(self._schemas) + 1)
                self._file.add_schema(sid, codec.type_name, schema_encoding, schema)
            self._file.add_channel(cid, topic, message_encoding(codec.mime), sid,
                                   {"zenoh_encoding": f"{codec.mime};{codec.type_name}",
                                    "qos": qos})
        return cid, codec

    def add(self, topic: str, msg: Any, log_time: int, qos: str = "rel+10") -> None:
        """Append ``msg`` (encoded as it travels on the wire) at ``log_time``; its
        publish time is its header's stamp when it has one, else ``log_time``."""
        cid, codec = self._channel(topic, msg, qos)
        data = codec.encode(msg)
        header = getattr(msg, "header", None)
        stamp = getattr(header, "stamp", None)
        publish = stamp.nanoseconds if stamp is not None else log_time
        seq = self._seq[cid] = self._seq.get(cid, 0) + 1
        self._chunk.add(cid, seq, log_time, max(0, publish), data)
        self._bytes += len(data) + 31
        self.count += 1
        if self._bytes >= CHUNK_BYTES:
            self._flush()

    def _flush(self) -> None:
        if self._bytes:
            self._file.write_chunk(self._chunk)
            self._chunk, self._bytes = ChunkBuffer(), 0

    def close(self) -> None:
        """Write the last chunk and the summary."""
        if self._file.closed:
            return
        self._flush()
        self._file.finish()
