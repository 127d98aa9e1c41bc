"""The MCAP writer and the bag sink: files the mcap library reads back, splitting."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from mcap.reader import make_reader
from zenros.bag import BagSink, SplitPolicy, bag_files, bag_info, iter_messages
from zenros.bag.writer import MESSAGE_HEAD, ChunkBuffer, McapFile

from .conftest import T0, twist, write_file


@pytest.mark.parametrize("compression", ["zstd", "lz4", "none"])
def test_file_round_trip(tmp_path: Path, compression: str) -> None:
    path = tmp_path / "a.mcap"
    write_file(path, chunks=3, per_chunk=100, compression=compression)
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None and summary.statistics is not None
        assert summary.statistics.message_count == 300
        assert summary.statistics.channel_message_counts == {1: 225, 2: 75}
        assert {c.compression for c in summary.chunk_indexes} == {
            "" if compression == "none" else compression}
        msgs = list(reader.iter_messages(topics=["/cmd_vel"], log_time_order=True))
    assert len(msgs) == 225
    assert [json.loads(m.data)["linear"]["x"] for _, _, m in msgs[:3]] == [1.0, 2.0, 3.0]
    assert msgs[0][2].sequence == 2 and msgs[0][2].log_time == T0 + 10_000_000
    assert msgs[0][1].metadata == {"qos": "rel+10"}


def test_time_filtered_read(tmp_path: Path) -> None:
    path = tmp_path / "t.mcap"
    write_file(path, chunks=4, per_chunk=50)
    got = list(iter_messages([path], start=T0 + 150 * 10_000_000))
    assert len(got) == 50
    assert got[0].log_time == T0 + 150 * 10_000_000


def test_unknown_compression_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="unknown compression 'gzip'"):
        McapFile(tmp_path / "x.mcap", "gzip")
    with pytest.raises(ValueError, match="unknown compression"):
        BagSink(tmp_path / "bag", "bag", compression="gzip")


def _fill(sink: BagSink, n: int, gap_ns: int = 1_000_000) -> None:
    cid = sink.add_channel("/cmd_vel", "json", "geometry_msgs/Twist", "jsonschema", b"{}")
    for i in range(n):
        sink.add(cid, T0 + i * gap_ns, T0, twist(i) + b" " * 200)
        if i % 50 == 49:
            sink.flush()


def test_sink_splits_by_size(tmp_path: Path) -> None:
    sink = BagSink(tmp_path / "bag", "bag", compression="none", chunk_size=4000,
                   split=SplitPolicy(max_bytes=20_000))
    _fill(sink, 500)
    sink.close()
    files = bag_files(tmp_path / "bag")
    assert len(files) >= 4
    assert [f.name for f in files[:2]] == ["bag_0.mcap", "bag_1.mcap"]
    info = bag_info(tmp_path / "bag")
    assert info.messages == 500
    xs = [json.loads(m.data)["linear"]["x"] for m in iter_messages(files)]
    assert xs == [float(i) for i in range(500)]
    for f in files:  # every file is self-contained: its own schema and channel
        assert bag_info(f).topics[0].type == "geometry_msgs/Twist"


def test_sink_splits_by_duration(tmp_path: Path) -> None:
    sink = BagSink(tmp_path / "bag", "bag", split=SplitPolicy(max_seconds=0.1))
    _fill(sink, 500)  # 0.5 s of messages, flushed every 50 ms
    sink.close()
    assert len(bag_files(tmp_path / "bag")) >= 3
    assert bag_info(tmp_path / "bag").messages == 500


def test_sink_sequences_count_per_channel(tmp_path: Path) -> None:
    sink = BagSink(tmp_path / "bag", "bag")
    a = sink.add_channel("/a", "json", "", "", b"")
    b = sink.add_channel("/b", "json", "", "", b"")
    for _ in range(3):
        sink.add(a, T0, T0, b"{}")
    sink.add(b, T0, T0, b"{}")
    sink.close()
    assert sink.message_count == 4
    seqs = [(m.channel.topic, m.sequence) for m in iter_messages(bag_files(tmp_path / "bag"))]
    assert sorted(seqs) == [("/a", 1), ("/a", 2), ("/a", 3), ("/b", 1)]


def _records(n: int) -> tuple[ChunkBuffer, list[bytes]]:
    """The same ``n`` messages on two interleaved channels, added one by one and as parts."""
    chunk, parts = ChunkBuffer(), []
    for i in range(n):
        channel, data = (1 if i % 3 else 2), twist(i) + b" " * (i % 7)
        chunk.add(channel, i + 1, T0 + i, T0 - i, data)
        parts += [MESSAGE_HEAD.pack(5, 22 + len(data), channel, i + 1, T0 + i, T0 - i), data]
    return chunk, parts


def test_chunk_of_records_matches_one_by_one() -> None:
    chunk, parts = _records(50)
    packed = ChunkBuffer.of_records(parts)
    assert bytes(packed.buf) == bytes(chunk.buf)
    assert set(packed.index) == {1, 2}
    for channel, idx in chunk.index.items():
        assert list(packed.index[channel]) == list(idx)  # (log time, offset) pairs
    single = ChunkBuffer.of_records(parts[2:4] + parts[4:6])  # one channel: the fast path
    assert list(single.index) == [1] and len(single.index[1]) == 4
    assert ChunkBuffer.of_records([]).index == {}


def test_sink_batches_split_into_chunks(tmp_path: Path) -> None:
    """`add_batch` batches larger than a chunk are cut at the record that fills it; message
    indexes, counts and order survive."""
    _, parts = _records(300)
    sink = BagSink(tmp_path / "bag", "bag", compression="none", chunk_size=2000)
    for channel in (1, 2):
        sink.add_channel(f"/c{channel}", "json", "", "", b"")
    for i in range(0, len(parts), 128):
        sink.add_batch(parts[i:i + 128])
    assert sink.message_count == 300
    sink.close()
    (path,) = bag_files(tmp_path / "bag")
    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None and summary.statistics is not None
    assert summary.statistics.channel_message_counts == {1: 200, 2: 100}
    assert len(summary.chunk_indexes) >= 300 * 60 // 2000
    assert all(c.uncompressed_size < 2000 + 100 for c in summary.chunk_indexes)
    got = [(m.log_time, m.sequence, m.publish_time) for m in iter_messages([path])]
    assert got == [(T0 + i, i + 1, T0 - i) for i in range(300)]
