"""zenros.message_filters' core, no Zenoh: the cases ROS's own message_filters tests cover.

The ApproximateTime cases are those of ROS 2's test_approximate_time_policy.cpp (inputs as
(second, topic), the sets expected in order), ExactTime those of test_exact_time_policy.cpp,
Cache and the Python synchronizer those of test_message_filters_cache.py / test_approxsync.py.
"""

from __future__ import annotations

import itertools
import logging
import random
from typing import Any

import pytest
from zenros.clock import ManualClock
from zenros.message_filters import (
    ApproximateTimeSynchronizer,
    Cache,
    SimpleFilter,
    TimeSynchronizer,
    stamp_ns,
)
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import PointStamped
from zenros.msgs.std_msgs import Header, String

S = 1_000_000_000


def msg(sec: float, tag: Any = None) -> PointStamped:
    m = PointStamped(header=Header(stamp=Time.from_seconds(sec)))
    m.header.frame_id = str(tag) if tag is not None else ""
    return m


def secs(m: Any) -> float:
    ns = stamp_ns(m)
    assert ns is not None
    return ns / S


def run_approx(inputs: list[tuple[float, int]], n: int, queue_size: int,
               **kw: Any) -> list[tuple[tuple[float, ...], int]]:
    """Feed ``inputs`` and return each emitted set's stamps with the input index it came on."""
    fs = [SimpleFilter() for _ in range(n)]
    sync = ApproximateTimeSynchronizer(fs, queue_size, **kw)
    out: list[tuple[tuple[float, ...], int]] = []
    step = 0
    sync.registerCallback(lambda *ms: out.append((tuple(secs(m) for m in ms), step)))
    for step, (t, topic) in enumerate(inputs):
        fs[topic].signalMessage(msg(t))
    return out


def sets(out: list[tuple[tuple[float, ...], int]]) -> list[tuple[float, ...]]:
    return [s for s, _ in out]


# ------------------------------------------------------------------ ApproximateTime (C++ tests)

def test_exact_match() -> None:
    inp = [(0, 0), (0, 1), (3, 0), (3, 1), (6, 0), (6, 1)]
    assert sets(run_approx(inp, 2, 10)) == [(0, 0), (3, 3), (6, 6)]


def test_perfect_match_waits_for_the_last_pair() -> None:
    inp = [(0, 0), (1, 1), (3, 0), (4, 1), (6, 0), (7, 1)]
    out = run_approx(inp, 2, 10)
    assert sets(out) == [(0, 1), (3, 4)]  # (6, 7) waits: a closer B could still come
    assert [step for _, step in out] == [2, 4]  # each emitted when the next A proves it


def test_imperfect_match_skips_the_stray_message() -> None:
    inp = [(0, 0), (1, 1), (2, 0), (3, 0), (5, 1), (6, 0), (7, 1)]
    assert sets(run_approx(inp, 2, 10)) == [(0, 1), (6, 5)]


def test_acceleration() -> None:
    inp = [(0, 0), (7, 1), (12, 0), (15, 1), (17, 0), (18, 1)]
    assert sets(run_approx(inp, 2, 10)) == [(12, 7), (17, 18)]


DROPPED = [(0, 0), (1, 1), (3, 1), (4, 0), (7, 1), (8, 0), (10, 0), (11, 1), (13, 0), (14, 1)]


def test_queue_of_one_loses_sets() -> None:
    assert sets(run_approx(DROPPED, 2, 1)) == [(4, 3), (10, 11)]


def test_queue_of_two_keeps_them() -> None:
    assert sets(run_approx(DROPPED, 2, 2)) == [(0, 1), (4, 3), (8, 7), (10, 11)]


def test_long_queue() -> None:
    inp = [(t, 0) for t in range(9)] + [(3, 1)] + [(t, 0) for t in (9, 10, 11, 12)] \
        + [(10, 1), (13, 0)]
    assert sets(run_approx(inp, 2, 5)) == [(10, 10)]


def test_one_arrival_emits_two_sets() -> None:
    out = run_approx([(0, 0), (1, 1), (3, 1), (3, 0)], 2, 10)
    assert out == [((0, 1), 3), ((3, 3), 3)]


def test_four_topics() -> None:
    inp = [(0, 0), (1, 1), (2, 2), (3, 3), (5, 0), (5, 3), (6, 1), (6, 2), (8, 0), (9, 1),
           (10, 2), (11, 3), (10, 0), (13, 0), (14, 1)]
    assert sets(run_approx(inp, 4, 10)) == [(0, 1, 2, 3), (5, 6, 6, 5), (10, 9, 10, 11)]


def test_early_publish() -> None:
    out = run_approx([(0, 0), (1, 1), (2, 2), (3, 3), (7, 0)], 4, 10)
    assert out == [((0, 1, 2, 3), 4)]


RATE = [(0, 0), (1, 1), (3, 0), (4, 1), (6, 0), (7, 1)]


def test_a_rate_bound_too_small_proves_nothing_more() -> None:
    out = run_approx(RATE, 2, 10, inter_message_lower_bounds=[1.5, 0])
    assert sets(out) == [(0, 1), (3, 4)]


def test_a_rate_bound_of_two_seconds_emits_the_last_pair_early() -> None:
    out = run_approx(RATE, 2, 10, inter_message_lower_bounds=[2, 0])
    assert out == [((0, 1), 1), ((3, 4), 3), ((6, 7), 5)]  # each as soon as its B arrives


# ------------------------------------------------------------------ slop, headerless, Python's

def test_slop_bounds_the_span_of_a_set() -> None:
    inp = [(0, 0), (1, 1), (1.05, 0), (2, 1), (2.02, 0), (3, 1), (3.5, 0)]
    assert sets(run_approx(inp, 2, 10, slop=0.1)) == [(1.05, 1), (2.02, 2)]


def test_pairs_with_equal_stamps_emit_at_once() -> None:
    """test_approxsync.py: each pair emitted as its second message arrives."""
    m0, m1 = SimpleFilter(), SimpleFilter()
    ts = ApproximateTimeSynchronizer([m0, m1], 1, 0.1)
    got: list[tuple[Any, ...]] = []
    ts.registerCallback(lambda *ms: got.append(ms))
    for t in range(10):
        got.clear()
        a, b = msg(t, 33), msg(t, 34)
        m0.signalMessage(a)
        assert got == []
        m1.signalMessage(b)
        assert got == [(a, b)]


@pytest.mark.parametrize("n", range(1, 10))
def test_in_order_sequences_recombine(n: int) -> None:
    """test_approxsync.py's sequences of length N (fed in stamp order: the C++ policy, as
    ROS documents it, assumes each topic's stamps rise)."""
    m0, m1 = SimpleFilter(), SimpleFilter()
    ts = ApproximateTimeSynchronizer([m0, m1], n, 0.1)
    got: list[tuple[Any, ...]] = []
    ts.registerCallback(lambda *ms: got.append(ms))
    seq0 = [msg(t, random.random()) for t in range(n)]
    seq1 = [msg(t, random.random()) for t in range(n)]
    for m in seq0:
        m0.signalMessage(m)
    assert got == []
    for m in seq1:
        m1.signalMessage(m)
    assert got == list(zip(seq0, seq1))


def test_headerless_messages_take_the_clock_when_allowed() -> None:
    clock = ManualClock(Time(sec=100))
    m0, m1 = SimpleFilter(), SimpleFilter()
    ts = ApproximateTimeSynchronizer([m0, m1], 10, 10, allow_headerless=True, clock=clock)
    got: list[tuple[Any, ...]] = []
    ts.registerCallback(lambda *ms: got.append(ms))
    stamped = [msg(100 + t) for t in range(3)]
    plain = [String(data=str(t)) for t in range(3)]
    for t in range(3):
        m0.signalMessage(stamped[t])
        clock.set(Time(sec=100 + t))
        m1.signalMessage(plain[t])
    m0.signalMessage(msg(110))
    assert got == list(zip(stamped, plain))


def test_headerless_messages_are_dropped_with_a_warning(caplog: pytest.LogCaptureFixture) -> None:
    m0, m1 = SimpleFilter(), SimpleFilter()
    ts = ApproximateTimeSynchronizer([m0, m1], 10, 1)
    got: list[tuple[Any, ...]] = []
    ts.registerCallback(lambda *ms: got.append(ms))
    with caplog.at_level(logging.WARNING, "zenros.message_filters"):
        m0.signalMessage(msg(0))
        m1.signalMessage(String(data="x"))
    assert got == [] and "no header.stamp" in caplog.text


def test_callback_args_follow_the_messages() -> None:
    m0, m1 = SimpleFilter(), SimpleFilter()
    ts = ApproximateTimeSynchronizer([m0, m1], 10)
    got: list[tuple[Any, ...]] = []
    ts.registerCallback(lambda *a: got.append(a), "extra")
    a, b = msg(1), msg(1)
    m0.signalMessage(a)
    m1.signalMessage(b)
    assert got == [(a, b, "extra")]


@pytest.mark.parametrize("kw", [{"queue_size": 0}, {"slop": -1}, {"age_penalty": -0.5},
                                {"inter_message_lower_bounds": [1.0]}])
def test_bad_arguments_are_refused(kw: dict[str, Any]) -> None:
    args: dict[str, Any] = {"queue_size": 10} | kw
    with pytest.raises(ValueError):
        ApproximateTimeSynchronizer([SimpleFilter(), SimpleFilter()], **args)


def test_one_input_is_refused() -> None:
    with pytest.raises(ValueError, match="at least 2"):
        ApproximateTimeSynchronizer([SimpleFilter()], 10)


def test_random_streams_keep_the_policy_invariants() -> None:
    """Every message used once, sets in order and never crossing, on 3 jittery topics."""
    rng = random.Random(7)
    inputs = sorted(((k * 0.1 + rng.uniform(-0.03, 0.03), topic)
                     for k in range(300) for topic in range(3)), key=lambda x: x[0] + 0.02)
    out = sets(run_approx(inputs, 3, 5, slop=0.08))
    assert len(out) > 250
    for s in out:
        assert max(s) - min(s) <= 0.08 + 1e-9
    for prev, nxt in itertools.pairwise(out):
        assert all(p < q for p, q in zip(prev, nxt))  # per topic, strictly later


# ------------------------------------------------------------------ ExactTime (C++ tests)

def exact(n: int, q: int) -> tuple[list[SimpleFilter], list[tuple[Any, ...]], list[tuple[Any, ...]]]:
    fs = [SimpleFilter() for _ in range(n)]
    sync = TimeSynchronizer(fs, q)
    got: list[tuple[Any, ...]] = []
    dropped: list[tuple[Any, ...]] = []
    sync.registerCallback(lambda *ms: got.append(ms))
    sync.registerDropCallback(lambda *ms: dropped.append(ms))
    return fs, got, dropped


def test_exact_multiple_times() -> None:
    fs, got, _ = exact(3, 2)
    fs[0].signalMessage(msg(0))
    late = msg(0.1)
    fs[1].signalMessage(late)
    fs[0].signalMessage(late)
    assert got == []
    fs[2].signalMessage(late)
    assert got == [(late, late, late)]


def test_exact_queue_size_evicts_partial_sets() -> None:
    fs, got, _ = exact(3, 1)
    fs[0].signalMessage(msg(0))
    fs[1].signalMessage(msg(0))
    fs[1].signalMessage(msg(0.1))
    fs[1].signalMessage(msg(0))
    fs[2].signalMessage(msg(0))
    assert got == []


def test_exact_drop_callback() -> None:
    fs, _got, dropped = exact(2, 1)
    first = msg(0)
    fs[0].signalMessage(first)
    assert dropped == []
    fs[0].signalMessage(msg(0.1))
    assert dropped == [(first, None)]


def test_exact_emission_drops_older_partial_sets() -> None:
    fs, got, dropped = exact(2, 10)
    old = msg(1)
    fs[0].signalMessage(old)
    a, b = msg(2), msg(2)
    fs[0].signalMessage(a)
    fs[1].signalMessage(b)
    assert got == [(a, b)] and dropped == [(old, None)]


# ------------------------------------------------------------------ Cache (Python tests)

def test_cache_all_functions() -> None:
    src = SimpleFilter()
    cache = Cache(src, 5)
    for t in range(5):
        src.signalMessage(msg(t))
    assert len(cache.getInterval(Time(sec=2), Time(sec=2))) == 1
    assert len(cache.getInterval(Time(sec=2), Time(sec=3))) == 2
    assert len(cache.getInterval(Time(), Time(sec=4))) == 5
    assert secs(cache.getElemAfterTime(Time())) == 0
    assert secs(cache.getElemBeforeTime(Time.from_seconds(3.5))) == 3
    assert cache.getLatestTime() == Time(sec=4) == cache.getLastestTime()
    assert cache.getOldestTime() == Time()
    src.signalMessage(msg(5))
    assert cache.getOldestTime() == Time(sec=1)  # the oldest went
    assert secs(cache.getLast()) == 5
    assert cache.getElemAfterTime(Time(sec=6)) is None
    assert cache.getElemBeforeTime(Time()) is None


def test_cache_headerless() -> None:
    src = SimpleFilter()
    cache = Cache(src, 5, allow_headerless=False)
    src.signalMessage(String(data="x"))
    assert cache.getElemAfterTime(Time()) is None
    clock = ManualClock(Time(sec=50))
    cache = Cache(src, 5, allow_headerless=True, clock=clock)
    m = String(data="y")
    src.signalMessage(m)
    assert cache.getElemAfterTime(Time(sec=50)) is m
    assert cache.getElemAfterTime(Time(sec=51)) is None
    assert cache.getInterval(Time(), Time(sec=50)) == [m]
    src.signalMessage(m)
    assert cache.getInterval(Time(), Time(sec=50)) == [m, m]


def test_cache_passes_messages_on_and_checks_its_arguments() -> None:
    src = SimpleFilter()
    cache = Cache(src, 2)
    seen: list[Any] = []
    cache.registerCallback(seen.append)
    m = msg(1)
    src.signalMessage(m)
    assert seen == [m] and cache.getLast() is m
    with pytest.raises(ValueError):
        cache.getInterval(Time(sec=3), Time(sec=1))
    with pytest.raises(ValueError):
        Cache(src, 0)
    with pytest.raises(TypeError):
        cache.getElemAfterTime("soon")  # type: ignore[arg-type]
    assert cache.getElemAfterTime(1 * S) is m  # integer nanoseconds are accepted
