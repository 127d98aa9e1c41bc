"""`zenros.json_chunks`: large messages encoded a slice at a time, byte for byte as
`json_bytes`, on a worker that keeps order."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from zenros import json_chunks as json_chunks_module
from zenros.codec import json_bytes
from zenros.json_chunks import (
    BULK_ELEMENTS,
    CHUNK,
    PACE,
    BulkEncoder,
    encode_yielding,
    is_bulky,
    json_chunks,
)
from zenros.message import Float32Array, Int8Array, to_array
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry
from zenros.msgs.sensor_msgs import LaserScan


def big_grid(cells: int = BULK_ELEMENTS + 3 * CHUNK + 7) -> OccupancyGrid:
    data = np.resize(np.array([-1, 0, 100, 0, 0], dtype=np.int8), cells)
    msg = OccupancyGrid(data=to_array(Int8Array, data))
    msg.header.frame_id = "map"
    msg.info.width, msg.info.height = cells, 1
    return msg


def test_same_bytes_as_json_bytes() -> None:
    grid = big_grid()
    assert len(list(json_chunks(grid))) > 5  # really in slices
    assert encode_yielding(grid) == json_bytes(grid)
    scan = LaserScan(ranges=to_array(Float32Array,
                                     np.linspace(0, 10, 3 * CHUNK, dtype=np.float32)))
    scan.ranges[3], scan.ranges[4] = np.nan, np.inf  # null, as json_bytes writes them
    assert encode_yielding(scan) == json_bytes(scan)
    odom = Odometry()
    odom.pose.covariance[0] = 0.5
    assert list(json_chunks(odom)) == [json_bytes(odom)]  # small: one piece


def test_is_bulky() -> None:
    assert is_bulky(big_grid())
    assert not is_bulky(Odometry()) and not is_bulky(big_grid(100))


def test_encoding_a_map_leaves_other_threads_running() -> None:
    """While the worker encodes a large map, another thread gets the GIL many times."""
    grid = big_grid(4 * 1024 * 1024)
    ticks = [0]
    done = threading.Event()

    def other() -> None:
        while not done.is_set():
            ticks[0] += 1
            done.wait(0.001)

    t = threading.Thread(target=other)
    t.start()
    bulk = BulkEncoder()
    try:
        before = ticks[0]
        future = bulk.submit(lambda: encode_yielding(grid))
        assert future is not None
        out = future.result(60)
        during = ticks[0] - before
    finally:
        done.set()
        t.join()
        bulk.close()
    assert out == json_bytes(grid)
    assert during >= 10, f"the other thread ran only {during} times during the encoding"


def test_bulk_encoder_keeps_order() -> None:
    bulk = BulkEncoder()
    seen: list[int] = []
    try:
        futures = [bulk.submit(lambda i=i: seen.append(i)) for i in range(50)]
        for f in futures:
            assert f is not None
            f.result(10)
    finally:
        bulk.close()
    assert seen == list(range(50))
    assert bulk.submit(lambda: None) is None  # closed: a late message is dropped, no error


def test_encoding_rests_twice_as_long_as_each_piece_took(monkeypatch: pytest.MonkeyPatch) -> None:
    """`encode_yielding` paces a large message: after each piece it sleeps ``rest`` times
    the time the piece took (`PACE` by default), so the encoding takes at most a third of a
    core and the small messages arriving meanwhile keep the rest."""
    now = [0.0]
    rests: list[float] = []

    def clock() -> float:
        now[0] += 0.001  # every reading of the clock: a piece took 1 ms
        return now[0]

    monkeypatch.setattr(json_chunks_module.time, "perf_counter", clock)
    monkeypatch.setattr(json_chunks_module.time, "sleep", rests.append)
    grid = big_grid()
    assert encode_yielding(grid) == json_bytes(grid)
    assert len(rests) == len(list(json_chunks(grid)))
    assert rests == pytest.approx([PACE * 0.001] * len(rests))
    rests.clear()
    encode_yielding(grid, rest=0.0)
    assert set(rests) == {0.0}  # only the GIL given away


def test_head_and_tail_go_around_the_json_in_one_join() -> None:
    grid = OccupancyGrid(data=to_array(Int8Array, np.arange(100_000) % 100))
    frame = encode_yielding(grid, rest=0.0, head=b'{"msg":', tail=b"}")
    assert frame == b'{"msg":' + json_bytes(grid) + b"}"
