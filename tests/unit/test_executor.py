"""executor and callbacks: the loop thread, callback groups, sync dispatch that logs errors,
async dispatch in order with a keep-last backlog, and stop() cancelling tasks."""

from __future__ import annotations

import asyncio
import logging
import threading
from collections.abc import Iterator
from typing import Any

import pytest
from zenros.callbacks import make_dispatch
from zenros.executor import (
    CallbackGroup,
    Executor,
    MutuallyExclusiveCallbackGroup,
    ReentrantCallbackGroup,
)
from zenros.log import ErrorLog

WAIT = 5.0
LOG = logging.getLogger("zenros_test.executor")


@pytest.fixture
def executor() -> Iterator[Executor]:
    ex = Executor(name="test-executor")
    yield ex
    ex.stop()


def barrier(ex: Executor) -> None:
    """Return once every callback already queued on the loop has run."""

    async def nothing() -> None:
        return None

    ex.submit(nothing()).result(WAIT)


class Recorder:
    """Collects values from any thread; waits on a condition for a count."""

    def __init__(self) -> None:
        self.items: list[Any] = []
        self.threads: list[str] = []
        self._cond = threading.Condition()

    def add(self, item: Any) -> None:
        with self._cond:
            self.items.append(item)
            self.threads.append(threading.current_thread().name)
            self._cond.notify_all()

    def wait_count(self, n: int) -> list[Any]:
        with self._cond:
            assert self._cond.wait_for(lambda: len(self.items) >= n, WAIT), self.items
            return list(self.items)


# ------------------------------------------------------------------ executor


def test_call_soon_runs_on_the_loop_thread(executor: Executor) -> None:
    rec = Recorder()
    executor.call_soon(lambda: rec.add(executor.in_loop_thread))
    assert rec.wait_count(1) == [True]
    assert rec.threads == ["test-executor"]
    assert not executor.in_loop_thread


def test_submit_returns_a_future(executor: Executor) -> None:
    async def add(a: int, b: int) -> int:
        await asyncio.sleep(0)
        return a + b

    assert executor.submit(add(2, 3)).result(WAIT) == 5


def test_wait_for_work(executor: Executor) -> None:
    assert executor.wait_for_work(0.01) is False
    done = threading.Event()

    def work() -> None:
        executor.mark_work()
        done.set()

    waiter_result: list[bool] = []
    started = threading.Event()

    def waiter() -> None:
        started.set()
        waiter_result.append(executor.wait_for_work(WAIT))

    th = threading.Thread(target=waiter)
    th.start()
    assert started.wait(WAIT)
    # keep marking work until the waiter has seen one (it may not be waiting yet)
    while th.is_alive():
        executor.call_soon(work)
        assert done.wait(WAIT)
        done.clear()
        th.join(0.01)
    assert waiter_result == [True]


def test_stop_cancels_pending_tasks_and_joins() -> None:
    ex = Executor()
    cancelled = threading.Event()
    running = threading.Event()

    async def forever() -> None:
        running.set()
        try:
            await asyncio.Event().wait()
        except asyncio.CancelledError:
            cancelled.set()
            raise

    fut = ex.submit(forever())
    assert running.wait(WAIT)
    ex.stop()
    assert cancelled.is_set()
    assert fut.cancelled()
    assert ex.loop.is_closed()  # closed only once its thread has ended


def test_stop_is_idempotent_and_call_soon_after_stop_is_ignored() -> None:
    ex = Executor()
    ex.stop()
    ex.stop()
    ex.call_soon(lambda: None)  # no error on a closed loop


# ------------------------------------------------------------------ callback groups


def test_plain_group_runs_the_function() -> None:
    assert CallbackGroup().run(lambda a, b: a + b, 2, 3) == 5
    assert ReentrantCallbackGroup().run(len, "abc") == 3


def test_mutually_exclusive_group_is_reentrant_on_one_thread() -> None:
    group = MutuallyExclusiveCallbackGroup()
    assert group.run(lambda: group.run(lambda: 42)) == 42


def _overlap_seen(group: CallbackGroup | None, wait: float) -> bool:
    """Run two callbacks of ``group`` from two threads: did the second start while the first
    was still inside? (The first waits up to ``wait`` seconds for the second to enter.)"""
    first_inside = threading.Event()
    second_inside = threading.Event()
    overlap: list[bool] = []

    def first(_: Any) -> None:
        first_inside.set()
        overlap.append(second_inside.wait(wait))

    def second(_: Any) -> None:
        second_inside.set()

    ex = Executor()
    try:
        d1 = make_dispatch(first, executor=ex, logger=LOG, what="first", group=group)
        d2 = make_dispatch(second, executor=ex, logger=LOG, what="second", group=group)
        t1 = threading.Thread(target=d1, args=(None,))
        t1.start()
        assert first_inside.wait(WAIT)
        t2 = threading.Thread(target=d2, args=(None,))
        t2.start()
        t1.join(WAIT)
        t2.join(WAIT)
        assert second_inside.is_set()
    finally:
        ex.stop()
    return overlap[0]


def test_mutually_exclusive_group_serializes_two_threads() -> None:
    # proving that something does not happen needs a bound: 0.2 s
    assert _overlap_seen(MutuallyExclusiveCallbackGroup(), 0.2) is False


def test_reentrant_group_lets_callbacks_overlap() -> None:
    assert _overlap_seen(ReentrantCallbackGroup(), WAIT) is True
    assert _overlap_seen(None, WAIT) is True


def test_mutually_exclusive_group_never_runs_two_at_once(executor: Executor) -> None:
    group = MutuallyExclusiveCallbackGroup()
    active = [0]
    peak = [0]
    count = [0]

    def cb(_: Any) -> None:
        active[0] += 1
        peak[0] = max(peak[0], active[0])
        for _ in range(50):
            threading.current_thread()  # some work that may switch threads
        count[0] += 1
        active[0] -= 1

    dispatch = make_dispatch(cb, executor=executor, logger=LOG, what="cb", group=group)
    threads = [threading.Thread(target=lambda: [dispatch(i) for i in range(300)]) for _ in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join(WAIT)
    assert count[0] == 1200
    assert peak[0] == 1


# ------------------------------------------------------------------ sync dispatch


@pytest.mark.parametrize(
    "group", [None, ReentrantCallbackGroup(), MutuallyExclusiveCallbackGroup()],
    ids=["no-group", "reentrant", "exclusive"],
)
def test_sync_dispatch_runs_on_the_calling_thread(executor: Executor, group: Any) -> None:
    rec = Recorder()
    dispatch = make_dispatch(rec.add, executor=executor, logger=LOG, what="sub", group=group)
    dispatch(1)
    assert rec.items == [1]  # already done: no hop to the loop
    assert rec.threads == [threading.current_thread().name]


@pytest.mark.parametrize(
    "group", [None, MutuallyExclusiveCallbackGroup()], ids=["no-group", "exclusive"]
)
def test_sync_dispatch_errors_are_logged_not_raised(
    executor: Executor, group: Any, caplog: pytest.LogCaptureFixture
) -> None:
    seen: list[int] = []

    def cb(n: int) -> None:
        seen.append(n)
        if n == 1:
            raise ValueError("bad sample")

    dispatch = make_dispatch(cb, executor=executor, logger=LOG, what="subscription /odom",
                             group=group)
    with caplog.at_level(logging.ERROR, logger=LOG.name):
        dispatch(1)
        dispatch(2)
    assert seen == [1, 2]
    [record] = [r for r in caplog.records if r.name == LOG.name]
    assert record.getMessage() == "subscription /odom callback raised ValueError: bad sample"
    assert record.exc_info is not None and isinstance(record.exc_info[1], ValueError)


def test_exclusive_group_is_released_after_an_error(executor: Executor) -> None:
    group = MutuallyExclusiveCallbackGroup()

    def boom(_: Any) -> None:
        raise RuntimeError("x")

    make_dispatch(boom, executor=executor, logger=LOG, what="boom", group=group)(None)
    result: list[int] = []
    th = threading.Thread(target=lambda: result.append(group.run(lambda: 1)))
    th.start()
    th.join(WAIT)
    assert result == [1]


# ------------------------------------------------------------------ async dispatch


class AsyncGate:
    """An async callback (``gate.fn``) that records its argument; it can hold the first call."""

    def __init__(self, executor: Executor, hold_first: bool) -> None:
        self.rec = Recorder()
        self.entered = threading.Event()
        self.gate = asyncio.Event()
        if not hold_first:
            self.gate.set()
        self.executor = executor

        async def fn(arg: Any) -> None:
            self.entered.set()
            await self.gate.wait()
            self.rec.add(arg)

        self.fn = fn

    def release(self) -> None:
        self.executor.call_soon(self.gate.set)


def test_async_dispatch_runs_in_order_on_the_loop(executor: Executor) -> None:
    cb = AsyncGate(executor, hold_first=False)
    dispatch = make_dispatch(cb.fn, executor=executor, logger=LOG, what="async", depth=100)
    for i in range(50):
        dispatch(i)
    assert cb.rec.wait_count(50) == list(range(50))
    assert set(cb.rec.threads) == {"test-executor"}


def test_async_dispatch_drops_oldest_beyond_depth(
    executor: Executor, caplog: pytest.LogCaptureFixture
) -> None:
    cb = AsyncGate(executor, hold_first=True)
    dispatch: Any = make_dispatch(
        cb.fn, executor=executor, logger=LOG, what="async /scan", depth=3
    )
    with caplog.at_level(logging.WARNING, logger=LOG.name):
        dispatch(0)
        assert cb.entered.wait(WAIT)  # 0 is running and held; the rest queue up
        for i in range(1, 9):
            dispatch(i)
        barrier(executor)  # all enqueued
        cb.release()
        assert cb.rec.wait_count(4) == [0, 6, 7, 8]
    assert dispatch.dropped == 5
    warnings = [r.getMessage() for r in caplog.records if r.name == LOG.name]
    assert warnings and "async /scan: async callback backlog full" in warnings[0]


def test_async_dispatch_errors_are_logged_and_draining_goes_on(
    executor: Executor, caplog: pytest.LogCaptureFixture
) -> None:
    rec = Recorder()

    async def cb(n: int) -> None:
        if n % 2:
            raise ValueError(f"odd {n}")
        rec.add(n)

    errs = ErrorLog(LOG)
    dispatch = make_dispatch(cb, executor=executor, logger=LOG, what="async cb", errors=errs)
    with caplog.at_level(logging.ERROR, logger=LOG.name):
        for i in range(6):
            dispatch(i)
        assert rec.wait_count(3) == [0, 2, 4]
        barrier(executor)
    assert errs.count == 3  # every one counted, one logged per type and period
    errors = [r for r in caplog.records if r.name == LOG.name and r.levelno == logging.ERROR]
    assert [r.getMessage() for r in errors] == ["async cb callback raised ValueError: odd 1"]


def test_async_dispatch_marks_work(executor: Executor) -> None:
    async def cb(_: Any) -> None:
        return None

    dispatch = make_dispatch(cb, executor=executor, logger=LOG, what="w")
    start = executor._work_count
    for i in range(3):
        dispatch(i)
    with executor._work:
        assert executor._work.wait_for(lambda: executor._work_count >= start + 3, WAIT)


def test_stop_cancels_a_running_async_callback() -> None:
    ex = Executor()
    cb = AsyncGate(ex, hold_first=True)
    dispatch = make_dispatch(cb.fn, executor=ex, logger=LOG, what="held")
    dispatch(1)
    assert cb.entered.wait(WAIT)
    ex.stop()
    assert ex.loop.is_closed()
    assert cb.rec.items == []
