"""Per-frame statistics: rate, newest stamp, delay and authority (tf_monitor's figures)."""

from __future__ import annotations

import pytest
from zenros.msgs.builtin_interfaces import Time
from zenros.services.tf.monitor import FrameMonitor

NS = 1_000_000_000


def test_rate_delay_and_authority_of_a_dynamic_frame() -> None:
    m = FrameMonitor(window=10.0)
    for i in range(11):  # 10 Hz for 1 s, stamps 20 ms behind the receiver's clock
        t = 100 * NS + i * NS // 10
        m.record("base_link", "odom", "/chassis", t, static=False, now_ns=t + 20_000_000,
                 arrival=50.0 + i * 0.1)
    (f,) = m.frames(now=51.0)
    assert (f.frame_id, f.parent, f.authority, f.static) == ("base_link", "odom", "/chassis",
                                                            False)
    assert f.rate == pytest.approx(10.0)
    assert f.delay == pytest.approx(0.02) and f.max_delay == pytest.approx(0.02)
    assert f.most_recent == Time(sec=101) and f.count == 11


def test_out_of_order_stamps_keep_the_newest() -> None:
    m = FrameMonitor()
    m.record("a", "p", "x", 5 * NS, static=False, now_ns=6 * NS, arrival=0.0)
    m.record("a", "p", "x", 4 * NS, static=False, now_ns=7 * NS, arrival=0.1)
    (f,) = m.frames(now=0.1)
    assert f.most_recent == Time(sec=5)
    assert f.delay == pytest.approx(2.0) and f.max_delay == pytest.approx(3.0)


def test_a_frame_that_stops_drops_to_rate_zero_after_one_window() -> None:
    m = FrameMonitor(window=2.0)
    for i in range(5):
        m.record("a", "p", "x", i, static=False, now_ns=i, arrival=float(i) * 0.5)
    assert m.frames(now=2.0)[0].rate == pytest.approx(2.0)
    (f,) = m.frames(now=10.0)
    assert f.rate == 0.0 and f.count == 5 and f.delay == 0.0


def test_last_writer_is_the_authority_and_parent() -> None:
    m = FrameMonitor()
    m.record("a", "p", "/one", 1, static=False, now_ns=1, arrival=0.0)
    m.record("a", "q", "/two", 2, static=False, now_ns=2, arrival=0.1)
    (f,) = m.frames(now=0.1)
    assert (f.parent, f.authority) == ("q", "/two")


def test_statics_have_no_rate_or_delay_and_frames_are_sorted() -> None:
    m = FrameMonitor()
    m.record("laser", "base_link", "/urdf", 3 * NS, static=True, now_ns=9 * NS, arrival=0.0)
    m.record("laser", "base_link", "/urdf", 3 * NS, static=True, now_ns=9 * NS, arrival=1.0)
    m.record("imu", "base_link", "/urdf", 0, static=True, now_ns=9 * NS, arrival=1.0)
    imu, laser = m.frames(now=1.0)
    assert imu.frame_id == "imu" and laser.frame_id == "laser"
    assert laser.static and laser.rate == 0.0 and laser.delay == 0.0 and laser.count == 2
    assert laser.most_recent == Time(sec=3)


def test_a_frame_turning_static_starts_afresh() -> None:
    m = FrameMonitor()
    m.record("a", "p", "x", 1, static=False, now_ns=1, arrival=0.0)
    m.record("a", "p", "y", 0, static=True, now_ns=2, arrival=0.1)
    (f,) = m.frames(now=0.1)
    assert f.static and f.count == 1 and f.authority == "y"


def test_memory_is_bounded_and_clear_forgets() -> None:
    m = FrameMonitor(max_samples=3)
    for i in range(10):
        m.record("a", "p", "x", i, static=False, now_ns=i, arrival=i * 0.1)
    assert m.frames(now=0.9)[0].rate == pytest.approx(10.0)
    m.clear()
    assert m.frames(now=1.0) == []


def test_window_must_be_positive() -> None:
    with pytest.raises(ValueError, match="window"):
        FrameMonitor(window=0)
