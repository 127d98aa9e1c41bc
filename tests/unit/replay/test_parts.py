"""The stepped executor, the replay clock, the CLI's per-node parameters, nav's timed loop."""

from __future__ import annotations

import asyncio
import logging
from typing import Any

import pytest
from zenros.cli.replay import parse_node_params
from zenros.clock import Time
from zenros.errors import ConfigError
from zenros.replay import DeterministicExecutor, ReplayClock
from zenros.replay.nodes import replayable
from zenros.services.nav.motion.timed_loop import TimedLoop


def test_drain_runs_what_is_ready_in_order_and_reports_a_wall_clock_sleep(
        caplog: pytest.LogCaptureFixture) -> None:
    ex = DeterministicExecutor()
    seen: list[str] = []

    async def job(name: str) -> None:
        seen.append(name)
        await asyncio.sleep(0)
        seen.append(name + "'")

    ex.submit(job("a"))
    ex.submit(job("b"))
    assert seen == []  # nothing runs until the run drains
    ex.drain()
    assert seen == ["a", "b", "a'", "b'"]
    with caplog.at_level(logging.WARNING, "zenros.replay"):
        ex.submit(asyncio.sleep(3600))
        ex.drain()
    assert "wall-clock asyncio timer" in caplog.text
    ex.stop()
    assert ex.loop.is_closed()


def test_the_clock_says_its_next_deadline_and_never_blocks() -> None:
    ex = DeterministicExecutor()
    clock = ReplayClock(Time(sec=1))
    assert clock.next_due() is None
    assert clock.sleep_until(Time(sec=2)) is False  # at once
    ex.submit(clock.async_sleep_until(Time(sec=3)))
    ex.submit(clock.async_sleep_until(Time(sec=2)))
    ex.drain()
    assert clock.next_due() == 2 * 10**9
    clock.set(Time(sec=2))
    ex.drain()
    assert clock.next_due() == 3 * 10**9
    ex.stop()


def test_node_parameters_of_the_cli() -> None:
    assert parse_node_params(["nav:max_linear_vel:=0.4", "nav:map:=a.yaml"]) == {
        "nav": {"max_linear_vel": 0.4, "map": "a.yaml"}}
    for bad in ("max_linear_vel:=0.4", "nav:max_linear_vel=0.4", ":x:=1"):
        with pytest.raises(ConfigError, match="NODE:NAME:=VALUE"):
            parse_node_params([bad])


def test_an_unknown_service_names_the_known_ones() -> None:
    with pytest.raises(ConfigError, match="no replayable service 'navv'; known: nav"):
        replayable("navv")


class FakeNode:
    def __init__(self) -> None:
        self.t = 0.0
        self.callback: Any = None

    def create_timer(self, period: float, callback: Any) -> Any:
        self.callback = callback
        return self

    def cancel(self) -> None:
        self.callback = None

    def now(self) -> Time:
        return Time.from_nanoseconds(round(self.t * 1e9))


def test_the_timed_loop_rests_while_idle_until_woken_or_a_second_passed() -> None:
    node, steps, idle = FakeNode(), [], [True]
    loop = TimedLoop(node, 0.05, lambda: steps.append(node.t), idle=lambda: idle[0])
    loop.start()
    for i in range(1, 41):  # 2 s of 50 ms ticks
        node.t = i * 0.05
        if i == 10:
            loop.wake()
        node.callback()
    assert steps == pytest.approx([0.05, 0.5, 1.5])  # the first tick, the wake, 1 s later
    idle[0] = False
    node.t = 2.05
    node.callback()
    assert steps[-1] == pytest.approx(2.05) and loop.calls == 4
    loop.stop()
    assert node.callback is None
