"""clock: ManualClock wakes thread and asyncio waiters; Rate keeps start + k * period deadlines
and restarts its schedule when it falls behind. Time only moves when a test moves it."""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Callable, Iterator

import pytest
from zenros.clock import Clock, Duration, ManualClock, Rate, SteadyClock, SystemClock, Time
from zenros.testing import RecordingClock

WAIT = 5.0  # seconds: a bound for conditions that should hold at once
MS = 1_000_000


def t_ms(ms: int) -> Time:
    return Time.from_nanoseconds(ms * MS)


class Worker:
    """Runs a function in a thread; joined (and checked) at teardown."""

    def __init__(self) -> None:
        self.threads: list[threading.Thread] = []
        self.errors: list[AssertionError] = []

    def start(self, fn: Callable[[], object]) -> threading.Thread:
        def run() -> None:
            try:
                fn()
            except AssertionError as exc:  # reported by the fixture (others by pytest)
                self.errors.append(exc)

        th = threading.Thread(target=run, daemon=True)
        th.start()
        self.threads.append(th)
        return th


@pytest.fixture
def worker() -> Iterator[Worker]:
    w = Worker()
    yield w
    for th in w.threads:
        th.join(WAIT)
        assert not th.is_alive()
    assert not w.errors, w.errors


# ------------------------------------------------------------------ real clocks


def test_real_clocks_follow_the_system() -> None:
    before = time.time_ns()
    now = SystemClock().now().nanoseconds
    assert abs(now - before) < 60 * 1_000_000_000
    a = SteadyClock().now()
    b = SteadyClock().now()
    assert b >= a
    assert SystemClock.kind == "system" and SteadyClock.kind == "steady"


def test_real_clock_sleep_until_the_past_returns_at_once() -> None:
    clock = SteadyClock()
    assert clock.sleep_until(clock.now() - Duration(sec=1)) is True
    assert clock.sleep_until(clock.now() + Duration(sec=3600), timeout=0) is False


async def test_real_clock_async_sleep_until_the_past() -> None:
    clock = SystemClock()
    await asyncio.wait_for(clock.async_sleep_until(clock.now() - Duration(sec=1)), WAIT)


def test_clocks_satisfy_the_protocol() -> None:
    clocks: list[Clock] = [SystemClock(), SteadyClock(), ManualClock()]
    assert [c.kind for c in clocks] == ["system", "steady", "ros"]


# ------------------------------------------------------------------ ManualClock


def test_manual_clock_starts_where_told_and_moves_only_when_told() -> None:
    clock = ManualClock(Time(sec=100))
    assert clock.now() == Time(sec=100)
    assert not clock.active
    assert clock.now() == Time(sec=100)
    clock.advance(0.25)
    assert clock.now() == Time(sec=100, nanosec=250_000_000)
    assert clock.active
    clock.set(Time(sec=5))  # sim time may jump back
    assert clock.now() == Time(sec=5)
    assert ManualClock().now() == Time()


def test_sleep_until_a_past_or_present_time_returns_true_at_once() -> None:
    clock = ManualClock(Time(sec=2))
    assert clock.sleep_until(Time(sec=1)) is True
    assert clock.sleep_until(Time(sec=2)) is True


def test_sleep_until_times_out_when_nobody_moves_the_clock() -> None:
    clock = ManualClock()
    assert clock.sleep_until(Time(sec=1), timeout=0.01) is False
    assert clock.sleep_until(Time(sec=1), timeout=0) is False


def test_set_wakes_a_thread_waiter(worker: Worker) -> None:
    clock = ManualClock()
    woke_at: list[Time] = []
    waiting = threading.Event()

    def sleeper() -> None:
        waiting.set()
        assert clock.sleep_until(Time(sec=1), timeout=WAIT)
        woke_at.append(clock.now())

    th = worker.start(sleeper)
    assert waiting.wait(WAIT)
    clock.set(Time(nanosec=500_000_000))  # not yet
    clock.set(Time(sec=1, nanosec=1))
    th.join(WAIT)
    assert woke_at == [Time(sec=1, nanosec=1)]


def test_advance_wakes_several_thread_waiters(worker: Worker) -> None:
    clock = ManualClock()
    woke: list[int] = []
    lock = threading.Lock()
    for k in (3, 1, 2):
        def sleeper(k: int = k) -> None:
            assert clock.sleep_until(Time(sec=k), timeout=WAIT)
            with lock:
                woke.append(k)
        worker.start(sleeper)
    clock.advance(1.0)
    clock.advance(1.0)
    clock.advance(1.0)
    for th in worker.threads:
        th.join(WAIT)
    assert sorted(woke) == [1, 2, 3]


async def test_async_sleep_until_wakes_on_set_from_another_thread(worker: Worker) -> None:
    clock = ManualClock()
    task = asyncio.ensure_future(clock.async_sleep_until(Time(sec=2)))
    for _ in range(3):
        await asyncio.sleep(0)  # let the task register (a yield, not a wait)
    assert not task.done()
    worker.start(lambda: clock.set(Time(sec=1)))
    worker.threads[-1].join(WAIT)
    for _ in range(3):
        await asyncio.sleep(0)
    assert not task.done()
    worker.start(lambda: clock.set(Time(sec=2)))
    await asyncio.wait_for(task, WAIT)
    assert clock.now() == Time(sec=2)


async def test_async_sleep_until_the_past_returns_at_once() -> None:
    clock = ManualClock(Time(sec=3))
    await asyncio.wait_for(clock.async_sleep_until(Time(sec=3)), WAIT)
    await asyncio.wait_for(clock.async_sleep_until(Time(sec=1)), WAIT)


async def test_async_waiters_wake_only_when_their_deadline_passes() -> None:
    clock = ManualClock()
    order: list[int] = []

    async def sleeper(k: int) -> None:
        await clock.async_sleep_until(Time(sec=k))
        order.append(k)

    tasks = [asyncio.ensure_future(sleeper(k)) for k in (3, 1, 2)]
    await asyncio.sleep(0)
    clock.set(Time(sec=2))
    await asyncio.wait_for(asyncio.gather(tasks[1], tasks[2]), WAIT)
    assert sorted(order) == [1, 2]
    assert not tasks[0].done()
    clock.advance(1.0)
    await asyncio.wait_for(tasks[0], WAIT)
    assert sorted(order) == [1, 2, 3]


async def test_cancelled_async_waiter_is_harmless() -> None:
    clock = ManualClock()
    task = asyncio.ensure_future(clock.async_sleep_until(Time(sec=1)))
    await asyncio.sleep(0)
    task.cancel()
    with pytest.raises(asyncio.CancelledError):
        await task
    clock.set(Time(sec=2))  # must not raise


def test_set_after_a_waiters_loop_closed_does_not_raise() -> None:
    """A loop that waited on the clock and was then closed (a stopped executor) must not
    make later ``set`` calls fail."""
    clock = ManualClock()
    loop = asyncio.new_event_loop()
    try:
        task = loop.create_task(clock.async_sleep_until(Time(sec=1)))
        loop.run_until_complete(asyncio.sleep(0))
        task.cancel()
        loop.run_until_complete(asyncio.gather(task, return_exceptions=True))
    finally:
        loop.close()
    clock.set(Time(sec=2))
    assert clock.now() == Time(sec=2)


# ------------------------------------------------------------------ Rate


@pytest.mark.parametrize("hz", [0, -1, -0.5])
def test_rate_rejects_non_positive_hz(hz: float) -> None:
    with pytest.raises(ValueError, match="positive"):
        Rate(hz, ManualClock())


def test_rate_period() -> None:
    assert Rate(10, ManualClock()).period == Duration(nanosec=100_000_000)
    assert Rate(0.5, ManualClock()).period == Duration(sec=2)
    assert isinstance(Rate(1000).clock, SteadyClock)


def test_rate_deadlines_are_start_plus_k_periods(worker: Worker) -> None:
    """However late each wake-up is (within a period), the schedule does not drift."""
    start = 1_000  # ms
    clock = RecordingClock(t_ms(start))
    rate = Rate(10, clock)  # 100 ms
    n = 8
    worker.start(lambda: [rate.sleep() for _ in range(n)])
    jitter = [0, 13, 99, 42, 1, 70, 55, 0]
    for k in range(n):
        deadline = clock.wait_requests(k + 1)[k]
        assert deadline == t_ms(start + 100 * (k + 1))
        clock.set(t_ms(start + 100 * (k + 1) + jitter[k]))  # wake up late, by jitter
    worker.threads[-1].join(WAIT)
    assert clock.requests == [t_ms(start + 100 * (k + 1)) for k in range(n)]


def test_rate_restarts_its_schedule_when_far_behind(worker: Worker) -> None:
    clock = RecordingClock(t_ms(0))
    rate = Rate(10, clock)
    worker.start(lambda: [rate.sleep() for _ in range(3)])
    assert clock.wait_requests(1)[0] == t_ms(100)
    clock.set(t_ms(1_234))  # the loop body took 11 periods: no burst of catch-up ticks
    assert clock.wait_requests(2)[1] == t_ms(1_334)
    clock.set(t_ms(1_334))
    assert clock.wait_requests(3)[2] == t_ms(1_434)
    clock.set(t_ms(1_434))
    worker.threads[-1].join(WAIT)


def test_rate_reset_restarts_from_now(worker: Worker) -> None:
    clock = RecordingClock(t_ms(0))
    rate = Rate(4, clock)  # 250 ms
    clock.set(t_ms(90))
    rate.reset()
    worker.start(rate.sleep)
    assert clock.wait_requests(1)[0] == t_ms(340)
    clock.set(t_ms(340))


async def test_async_rate_is_drift_free() -> None:
    clock = RecordingClock(t_ms(0))
    rate = Rate(20, clock)  # 50 ms
    for k in range(1, 5):
        task = asyncio.ensure_future(rate.async_sleep())
        await asyncio.sleep(0)
        assert clock.requests[-1] == t_ms(50 * k)
        clock.set(t_ms(50 * k + 17))
        await asyncio.wait_for(task, WAIT)
    assert clock.requests == [t_ms(50 * k) for k in range(1, 5)]


async def test_async_rate_restarts_when_far_behind() -> None:
    clock = RecordingClock(t_ms(0))
    rate = Rate(20, clock)
    clock.set(t_ms(1_000))
    await asyncio.wait_for(rate.async_sleep(), WAIT)  # deadline 50 ms already passed
    task = asyncio.ensure_future(rate.async_sleep())
    await asyncio.sleep(0)
    assert clock.requests[-1] == t_ms(1_050)
    clock.set(t_ms(1_050))
    await asyncio.wait_for(task, WAIT)
