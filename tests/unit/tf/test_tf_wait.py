"""Waiting for transforms: blocking timeouts on a condition, threads, and asyncio futures."""

from __future__ import annotations

import asyncio
import threading
import time

import pytest
from zenros.errors import (
    ExtrapolationException,
    LookupException,
    TimeoutException,
    TransformException,
)
from zenros.msgs.builtin_interfaces import Duration, Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.tf import Buffer
from tf_links import T, link

class SpyBuffer(Buffer):  # type: ignore[misc]
    """Sets ``checked`` when a waiter first tests its condition (under the buffer lock), so
    a feeder that waits for it can only insert once the waiter sleeps on the condition."""

    def __init__(self) -> None:
        super().__init__()
        self.checked = threading.Event()

    def _can(self, target: str, source: str, t: int) -> bool:
        self.checked.set()
        return bool(super()._can(target, source, t))


def feed_after_check(buf: SpyBuffer, *msgs: TransformStamped) -> threading.Thread:
    def run() -> None:
        assert buf.checked.wait(10)
        for m in msgs:
            buf.set_transform(m, "feeder")

    th = threading.Thread(target=run)
    th.start()
    return th


# ---------------------------------------------------------------- blocking


def test_blocking_lookup_wakes_on_insert() -> None:
    buf = SpyBuffer()
    buf.set_transform(link("map", "odom", 1.0), "me")
    th = feed_after_check(buf, link("map", "odom", 2.0, x=2.0))
    t0 = time.monotonic()
    out = buf.lookup_transform("map", "odom", T(2.0), timeout=30.0)
    assert time.monotonic() - t0 < 10.0  # woken by the insert, not by the timeout
    assert out.transform.translation.x == 2.0
    th.join()
    assert buf._waiters.blocked == 0 and buf._watchers == 0


def test_blocking_lookup_of_a_frame_that_appears_later() -> None:
    buf = SpyBuffer()
    th = feed_after_check(buf, link("map", "laser", 5.0, x=1.0))
    assert buf.can_transform("map", "laser", Time(), timeout=Duration(sec=30))
    assert buf.lookup_transform("map", "laser", Time()).header.stamp == T(5.0)
    th.join()


def test_timeout_raises_the_underlying_error() -> None:
    buf = Buffer()
    buf.set_transform(link("map", "odom", 1.0), "me")
    t0 = time.monotonic()
    with pytest.raises(ExtrapolationException, match="only time 1.000000000"):
        buf.lookup_transform("map", "odom", T(2.0), timeout=0.05)
    assert time.monotonic() - t0 >= 0.05
    with pytest.raises(LookupException):
        buf.lookup_transform("map", "nowhere", T(2.0), timeout=0.01)
    assert not buf.can_transform("map", "odom", T(2.0), timeout=0.01)
    assert buf._watchers == 0


def test_many_blocked_threads_are_all_woken() -> None:
    buf = Buffer()
    results: dict[int, float] = {}
    errors: list[BaseException] = []

    def waiter(i: int) -> None:
        try:
            m = buf.lookup_transform("root", f"c{i}", T(1.0), timeout=30.0)
            results[i] = m.transform.translation.x
        except BaseException as e:  # noqa: BLE001 - reported below
            errors.append(e)

    threads = [threading.Thread(target=waiter, args=(i,)) for i in range(8)]
    for th in threads:
        th.start()
    for i in range(8):
        buf.set_transform(link("root", f"c{i}", 1.0, x=float(i)), "feeder")
    for th in threads:
        th.join(30)
    assert not errors and results == {i: float(i) for i in range(8)}


def test_concurrent_inserts_and_lookups_are_consistent() -> None:
    buf = Buffer(cache_time=1.0)
    stop = threading.Event()
    failures: list[BaseException] = []

    def writer(k: int) -> None:
        for n in range(1, 3000):
            buf.set_transform(link(f"w{k}", f"w{k}_child", n / 100.0, x=float(k)), "w")
        buf.set_transform_static(link("root", f"w{k}", 1.0), "w")

    def reader() -> None:
        while not stop.is_set():
            for k in range(3):
                try:
                    m = buf.lookup_transform(f"w{k}", f"w{k}_child", Time())
                    assert m.transform.translation.x == float(k)
                except TransformException:
                    pass
                except BaseException as e:  # noqa: BLE001 - reported below
                    failures.append(e)
                    return

    readers = [threading.Thread(target=reader) for _ in range(2)]
    writers = [threading.Thread(target=writer, args=(k,)) for k in range(3)]
    for th in readers + writers:
        th.start()
    for th in writers:
        th.join()
    stop.set()
    for th in readers:
        th.join()
    assert not failures
    assert buf.lookup_transform("w0_child", "w2_child", Time()).header.stamp == T(29.99)


# ---------------------------------------------------------------- asyncio


async def test_async_wait_resolves_at_once_when_available() -> None:
    buf = Buffer()
    buf.set_transform(link("a", "b", 1.0), "me")
    fut = buf.wait_for_transform_async("a", "b", T(1.0))
    assert fut.done() and fut.result() is True
    await buf.wait_for_transform("a", "b", T(1.0), timeout=1.0)


async def test_async_wait_woken_from_another_thread() -> None:
    buf = Buffer()
    fut = buf.wait_for_transform_async("map", "base", T(3.0))
    assert not fut.done() and buf._watchers == 1
    th = threading.Thread(target=buf.set_transform, args=(link("map", "base", 3.0, x=7.0), "t"))
    th.start()
    assert await asyncio.wait_for(fut, 30) is True
    th.join()
    assert buf._watchers == 0 and buf._waiters.pending == []


async def test_async_wait_woken_on_the_loop_thread_and_lookup_async() -> None:
    buf = Buffer()
    task = asyncio.ensure_future(buf.lookup_transform_async("map", "base", T(3.0), timeout=30))
    await asyncio.sleep(0)  # let the task register its waiter
    buf.set_transform(link("map", "base", 2.0), "t")
    assert not task.done()
    buf.set_transform(link("map", "base", 3.0, x=4.0), "t")
    out = await asyncio.wait_for(task, 30)
    assert out.transform.translation.x == 4.0


async def test_async_timeout_and_cancel_clean_up() -> None:
    buf = Buffer()
    with pytest.raises(TimeoutException, match="Timed out waiting for transform from b to a"):
        await buf.wait_for_transform("a", "b", T(1.0), timeout=0.02)
    fut = buf.wait_for_transform_async("a", "b", T(1.0))
    fut.cancel()
    await asyncio.sleep(0)  # done-callbacks run on the next loop turn
    assert buf._waiters.pending == [] and buf._watchers == 0


async def test_async_wait_fails_fast_for_data_older_than_the_window() -> None:
    buf = Buffer(cache_time=10.0)
    buf.set_transform(link("a", "b", 100.0), "me")
    with pytest.raises(LookupException, match="Failed to transform from b to a"):
        await buf.wait_for_transform("a", "b", T(50.0), timeout=1.0)


async def test_one_insert_resolves_many_async_waiters() -> None:
    buf = Buffer()
    futs = [buf.wait_for_transform_async("a", f"c{i}", T(1.0)) for i in range(5)]
    futs.append(buf.wait_for_transform_async("a", "c0", Time()))
    for i in range(5):
        buf.set_transform(link("a", f"c{i}", 1.0), "t")
    assert await asyncio.wait_for(asyncio.gather(*futs), 30) == [True] * 6
