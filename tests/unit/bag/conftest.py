"""Bag test helpers: small MCAP files written with the bag writer."""

from __future__ import annotations

import json
from pathlib import Path

from zenros.bag.writer import ChunkBuffer, McapFile

T0 = 1_700_000_000 * 10**9


def twist(i: int) -> bytes:
    return json.dumps({"linear": {"x": float(i)}}).encode()


def write_file(path: Path, chunks: int, per_chunk: int, *, compression: str = "zstd",
               finish: bool = True) -> McapFile:
    """``chunks`` chunks of ``per_chunk`` Twists on /cmd_vel, 10 ms apart; finished or not."""
    f = McapFile(path, compression)
    f.add_schema(1, "geometry_msgs/Twist", "jsonschema", b'{"type":"object"}')
    f.add_channel(1, "/cmd_vel", "json", 1, {"qos": "rel+10"})
    f.add_channel(2, "/other", "json", 1)
    for c in range(chunks):
        chunk = ChunkBuffer()
        for k in range(per_chunk):
            i = c * per_chunk + k
            chunk.add(1 if i % 4 else 2, i + 1, T0 + i * 10_000_000, T0, twist(i))
        f.write_chunk(chunk)
    if finish:
        f.finish()
    else:
        f.abandon()
    return f
