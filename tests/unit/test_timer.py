"""Timer on a ManualClock: one call per period, drift-free deadlines, skipped ticks after a
jump, cancel/reset, errors logged. Time moves only when the test moves it; no sleeps."""

from __future__ import annotations

import asyncio
import itertools
import logging
import math
import threading
from collections.abc import Iterator
from typing import Any

import pytest
from zenros.clock import ManualClock, SteadyClock, Time
from zenros.executor import Executor, MutuallyExclusiveCallbackGroup
from zenros.testing import RecordingClock
from zenros.timer import Timer

WAIT = 5.0
MS = 1_000_000
LOG = logging.getLogger("zenros_test.timer")


def t_ms(ms: int) -> Time:
    return Time.from_nanoseconds(ms * MS)


class Calls:
    """A timer callback that counts its calls; tests wait on the count."""

    def __init__(self, clock: ManualClock, fail_on: set[int] | None = None) -> None:
        self.clock = clock
        self.at: list[Time] = []
        self.threads: set[str] = set()
        self.fail_on = fail_on or set()
        self._cond = threading.Condition()

    def __call__(self) -> None:
        with self._cond:
            self.at.append(self.clock.now())
            self.threads.add(threading.current_thread().name)
            self._cond.notify_all()
            n = len(self.at)
        if n in self.fail_on:
            raise RuntimeError(f"call {n} failed")

    def wait(self, n: int) -> list[Time]:
        with self._cond:
            assert self._cond.wait_for(lambda: len(self.at) >= n, WAIT), self.at
            return list(self.at)


@pytest.fixture
def executor() -> Iterator[Executor]:
    ex = Executor(name="timer-executor")
    yield ex
    ex.stop()


@pytest.fixture
def clock() -> RecordingClock:
    return RecordingClock(t_ms(10_000))


def drain(ex: Executor) -> None:
    """Let every wake-up already triggered on the loop run to completion."""

    async def nothing() -> None:
        await asyncio.sleep(0)

    for _ in range(3):
        ex.submit(nothing()).result(WAIT)


def make(clock: ManualClock, ex: Executor, cb: Any, period: float = 0.1, **kw: Any) -> Timer:
    return Timer(period, cb, clock, ex, LOG, **kw)


# ------------------------------------------------------------------ construction


@pytest.mark.parametrize("period", [0, -0.1, math.nan])
def test_non_positive_period_is_rejected(
    period: float, clock: RecordingClock, executor: Executor
) -> None:
    with pytest.raises(ValueError, match="period must be positive"):
        make(clock, executor, lambda: None, period)


def test_without_autostart_nothing_runs_until_reset(
    clock: RecordingClock, executor: Executor
) -> None:
    calls = Calls(clock)
    timer = make(clock, executor, calls, autostart=False)
    assert timer.is_canceled()
    clock.set(t_ms(20_000))
    drain(executor)
    assert calls.at == [] and clock.requests == []
    timer.reset()
    assert not timer.is_canceled()
    assert clock.wait_requests(1)[0] == t_ms(20_100)


# ------------------------------------------------------------------ ticking


def test_fires_once_per_period_on_the_executor(clock: RecordingClock, executor: Executor) -> None:
    calls = Calls(clock)
    timer = make(clock, executor, calls, period=0.1)
    assert clock.wait_requests(1)[0] == t_ms(10_100)
    clock.set(t_ms(10_050))  # half a period: nothing
    clock.set(t_ms(10_100))
    assert clock.wait_requests(2)[1] == t_ms(10_200)
    assert calls.at == [t_ms(10_100)]
    clock.set(t_ms(10_150))
    clock.set(t_ms(10_200))
    assert clock.wait_requests(3)[2] == t_ms(10_300)
    assert calls.wait(2) == [t_ms(10_100), t_ms(10_200)]
    assert timer.calls == 2
    assert calls.threads == {"timer-executor"}


def test_the_first_deadline_is_one_period_after_creation_however_busy_the_executor(
    clock: RecordingClock, executor: Executor
) -> None:
    held, release = threading.Event(), threading.Event()
    executor.call_soon(lambda: (held.set(), release.wait(WAIT)))
    assert held.wait(WAIT)
    calls = Calls(clock)
    make(clock, executor, calls, period=0.1)  # at 10.000 s
    clock.set(t_ms(10_050))  # the clock moves before the executor gets to the timer
    release.set()
    assert clock.wait_requests(1)[0] == t_ms(10_100)
    clock.set(t_ms(10_100))
    assert calls.wait(1) == [t_ms(10_100)]


def test_deadlines_do_not_drift(clock: RecordingClock, executor: Executor) -> None:
    calls = Calls(clock)
    make(clock, executor, calls, period=0.25)
    late = [0, 1, 249, 100, 30, 0, 200]  # each wake-up is late by this many ms
    for k, delay in enumerate(late, start=1):
        assert clock.wait_requests(k)[k - 1] == t_ms(10_000 + 250 * k)
        clock.set(t_ms(10_000 + 250 * k + delay))
    assert clock.wait_requests(len(late) + 1)[len(late)] == t_ms(10_000 + 250 * (len(late) + 1))
    assert len(calls.at) == len(late)


def test_a_jump_fires_once_and_skips_missed_ticks(
    clock: RecordingClock, executor: Executor
) -> None:
    calls = Calls(clock)
    make(clock, executor, calls, period=0.1)
    assert clock.wait_requests(1)[0] == t_ms(10_100)
    clock.set(t_ms(10_550))  # 4.5 periods late: one call, not five
    assert clock.wait_requests(2)[1] == t_ms(10_600)
    assert len(calls.at) == 1
    clock.set(t_ms(10_600))
    assert clock.wait_requests(3)[2] == t_ms(10_700)
    assert len(calls.wait(2)) == 2


def test_a_jump_onto_a_tick_continues_the_schedule(
    clock: RecordingClock, executor: Executor
) -> None:
    calls = Calls(clock)
    make(clock, executor, calls, period=0.1)
    clock.wait_requests(1)
    clock.set(t_ms(10_500))
    next_deadline = clock.wait_requests(2)[1]
    assert next_deadline == t_ms(10_600)
    assert (next_deadline - t_ms(10_000)).nanoseconds % (100 * MS) == 0
    assert len(calls.at) == 1


def test_async_callback(clock: RecordingClock, executor: Executor) -> None:
    calls = Calls(clock)

    async def cb() -> None:
        await asyncio.sleep(0)
        calls()

    make(clock, executor, cb, period=0.1)
    clock.wait_requests(1)
    clock.set(t_ms(10_100))
    assert calls.wait(1) == [t_ms(10_100)]


def test_callback_runs_inside_its_group(clock: RecordingClock, executor: Executor) -> None:
    group = MutuallyExclusiveCallbackGroup()
    held = threading.Event()
    release = threading.Event()
    calls = Calls(clock)

    def hold() -> None:
        held.set()
        release.wait(WAIT)

    def holder() -> None:  # another thread holds the group while the tick is due
        group.run(hold)

    make(clock, executor, calls, period=0.1, group=group)
    clock.wait_requests(1)
    th = threading.Thread(target=holder)
    th.start()
    assert held.wait(WAIT)
    clock.set(t_ms(10_100))
    release.set()
    th.join(WAIT)
    assert calls.wait(1) == [t_ms(10_100)]


# ------------------------------------------------------------------ errors


def test_callback_errors_are_logged_and_the_timer_keeps_running(
    clock: RecordingClock, executor: Executor, caplog: pytest.LogCaptureFixture
) -> None:
    calls = Calls(clock, fail_on={1, 2})
    with caplog.at_level(logging.ERROR, logger=LOG.name):
        make(clock, executor, calls, period=0.1)
        for k in range(1, 4):
            clock.wait_requests(k)
            clock.set(t_ms(10_000 + 100 * k))
        calls.wait(3)
        clock.wait_requests(4)
    errors = [r for r in caplog.records if r.name == LOG.name]
    assert [r.getMessage() for r in errors] == ["timer callback raised"] * 2
    assert all(r.exc_info is not None and isinstance(r.exc_info[1], RuntimeError) for r in errors)


# ------------------------------------------------------------------ cancel and reset


def test_cancel_stops_the_calls(clock: RecordingClock, executor: Executor) -> None:
    calls = Calls(clock)
    timer = make(clock, executor, calls, period=0.1)
    clock.wait_requests(1)
    clock.set(t_ms(10_100))
    clock.wait_requests(2)
    timer.cancel()
    assert timer.is_canceled()
    drain(executor)
    clock.set(t_ms(10_200))
    clock.set(t_ms(11_000))
    drain(executor)
    assert len(calls.at) == 1
    assert len(clock.requests) == 2


def test_cancel_twice_is_harmless(clock: RecordingClock, executor: Executor) -> None:
    timer = make(clock, executor, lambda: None)
    timer.cancel()
    timer.cancel()
    assert timer.is_canceled()


def test_reset_restarts_one_period_from_now(clock: RecordingClock, executor: Executor) -> None:
    calls = Calls(clock)
    timer = make(clock, executor, calls, period=1.0)
    assert clock.wait_requests(1)[0] == t_ms(11_000)
    clock.set(t_ms(10_600))
    timer.reset()
    assert clock.wait_requests(2)[1] == t_ms(11_600)
    drain(executor)
    clock.set(t_ms(11_000))  # the old deadline: the old schedule is gone
    drain(executor)
    assert calls.at == []
    clock.set(t_ms(11_600))
    assert calls.wait(1) == [t_ms(11_600)]
    assert clock.wait_requests(3)[2] == t_ms(12_600)
    assert len(calls.at) == 1


def test_reset_after_cancel(clock: RecordingClock, executor: Executor) -> None:
    calls = Calls(clock)
    timer = make(clock, executor, calls, period=0.5)
    clock.wait_requests(1)
    timer.cancel()
    clock.set(t_ms(12_000))
    drain(executor)
    timer.reset()
    assert clock.wait_requests(2)[1] == t_ms(12_500)
    clock.set(t_ms(12_500))
    assert calls.wait(1) == [t_ms(12_500)]


# ------------------------------------------------------------------ executor shutdown


def test_executor_stop_cancels_the_timer(clock: RecordingClock) -> None:
    ex = Executor()
    calls = Calls(clock)
    make(clock, ex, calls, period=0.1)
    clock.wait_requests(1)
    ex.stop()
    assert ex.loop.is_closed()
    assert calls.at == []


def test_clock_can_move_after_the_timers_executor_stopped(clock: RecordingClock) -> None:
    """A node closed (its executor stopped) while its timer slept must not break the clock
    for everyone else that shares it (sim time)."""
    ex = Executor()
    make(clock, ex, lambda: None, period=0.1)
    clock.wait_requests(1)
    ex.stop()
    clock.set(t_ms(10_100))
    assert clock.now() == t_ms(10_100)


# ------------------------------------------------------------------ on a real clock


class JumpClock(SteadyClock):
    """The steady clock, moved ahead by ``offset`` nanoseconds when a test says so."""

    def __init__(self) -> None:
        self.offset = 0

    def ns(self) -> int:
        return super().ns() + self.offset


class Ticks:
    """A callback recording the clock's nanoseconds at each call; tests wait on the count."""

    def __init__(self, clock: JumpClock, on_call: Any = None) -> None:
        self.clock = clock
        self.at: list[int] = []
        self.threads: set[str] = set()
        self.on_call = on_call
        self._cond = threading.Condition()

    def __call__(self) -> None:
        with self._cond:
            self.at.append(self.clock.ns())
            self.threads.add(threading.current_thread().name)
            self._cond.notify_all()
            n = len(self.at)
        if self.on_call is not None:
            self.on_call(n)

    def wait(self, n: int) -> list[int]:
        with self._cond:
            assert self._cond.wait_for(lambda: len(self.at) >= n, WAIT), self.at
            return list(self.at)


def test_on_a_real_clock_ticks_come_on_their_deadlines_and_skip_after_a_jump(
    executor: Executor,
) -> None:
    """A plain callback on a real clock ticks on the loop's own timer: never before its
    deadline, one tick a deadline; a clock jumping a second ahead gives one tick, then the
    schedule goes on from there (the missed ticks are skipped, not bunched)."""
    clock, period = JumpClock(), 20 * MS

    def jump(n: int) -> None:
        if n == 3:
            clock.offset += 1_000 * MS

    ticks = Ticks(clock, jump)
    start = clock.ns()
    timer = make(clock, executor, ticks, period=period / 1e9)
    at = ticks.wait(6)
    timer.cancel()
    slots = [(t - start) // period for t in at]
    assert slots[0] >= 1 and all(b > a for a, b in itertools.pairwise(slots))
    assert slots[3] - slots[2] >= 50  # the jump: 1 s of 20 ms deadlines passed at once
    assert ticks.threads == {"timer-executor"} and timer.calls >= 6


def test_on_a_real_clock_cancel_and_reset_stop_and_restart_the_ticks(
    executor: Executor,
) -> None:
    """A timer cancelled from its own callback ticks no more (while a witness beside it
    ticks on); reset starts it again."""
    clock = JumpClock()
    stopped: list[Timer] = []
    ticks = Ticks(clock, lambda n: stopped[0].cancel() if n == 2 else None)
    stopped.append(make(clock, executor, ticks, period=0.01))
    witness = Ticks(clock)
    make(clock, executor, witness, period=0.01)
    ticks.wait(2)
    witness.wait(len(witness.at) + 5)
    assert len(ticks.at) == 2 and stopped[0].is_canceled()
    stopped[0].reset()
    assert len(ticks.wait(4)) == 4 and not stopped[0].is_canceled()
