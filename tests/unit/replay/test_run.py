"""DeterministicRun: the order of timers and messages, exact timer times, direct dispatch
between the run's nodes, and the wall-clock check."""

from __future__ import annotations

import random
import time
from typing import Any

import pytest
from zenros import Node
from zenros.msgs.std_msgs import Int32, String
from zenros.replay import DeterministicRun

T0 = 5_000_000_000
MS = 1_000_000


class Ticker(Node):
    """Two timers (100 ms, created in that order) and a subscription to /in; writes what
    happens to ``log`` with the clock's time."""

    def setup(self) -> None:
        self.log: list[tuple[str, int]] = []
        self.create_timer(0.1, lambda: self.log.append(("a", self.now().nanoseconds)))
        self.create_timer(0.1, lambda: self.log.append(("b", self.now().nanoseconds)))
        self.create_subscription(Int32, "/in", lambda m: self.log.append(
            (f"msg{m.data}", self.now().nanoseconds)))


class Relay(Node):
    """/in -> /mid (doubled); a second node takes /mid -> /out (as text)."""

    def setup(self) -> None:
        pub = self.create_publisher(Int32, "/mid")
        self.create_subscription(Int32, "/in", lambda m: pub.publish(Int32(data=2 * m.data)))


class Sink(Node):
    def setup(self) -> None:
        pub = self.create_publisher(String, "/out")
        self.create_subscription(Int32, "/mid", lambda m: pub.publish(String(data=str(m.data))))


def test_timers_fire_at_their_exact_times_before_a_message_of_the_same_instant() -> None:
    with DeterministicRun(T0) as run:
        node: Any = run.add_node(Ticker)
        run.deliver("/in", Int32(data=1), T0 + 250 * MS)
        run.deliver("/in", Int32(data=2), T0 + 300 * MS)  # the timers' third deadline
        run.advance_to(T0 + 400 * MS)
        assert node.log == [
            ("a", T0 + 100 * MS), ("b", T0 + 100 * MS),
            ("a", T0 + 200 * MS), ("b", T0 + 200 * MS),
            ("msg1", T0 + 250 * MS),
            ("a", T0 + 300 * MS), ("b", T0 + 300 * MS), ("msg2", T0 + 300 * MS),
            ("a", T0 + 400 * MS), ("b", T0 + 400 * MS),
        ]
        assert run.timer_steps == 4  # one clock stop per deadline, both timers in each


def test_outputs_pass_between_the_runs_nodes_in_order_and_are_not_fed_back() -> None:
    outs: list[tuple[str, Any, int]] = []
    with DeterministicRun(T0, lambda topic, msg, t: outs.append((topic, getattr(msg, "data", None), t))) as run:
        run.add_node(Relay)
        run.add_node(Sink)
        assert run.subscribed("/in") and not run.subscribed("/mid")  # /mid is an output
        assert run.deliver("/in", Int32(data=3), T0 + MS) == 1
        assert run.deliver("/mid", Int32(data=100), T0 + 2 * MS) == 0  # a node publishes it
        assert run.deliver("/nobody", Int32(data=1), T0 + 3 * MS) == 0
    got = [o for o in outs if o[0] in ("/mid", "/out")]
    assert got == [("/mid", 6, T0 + MS), ("/out", "6", T0 + MS)]


def test_time_never_goes_back() -> None:
    with DeterministicRun(T0) as run:
        run.advance_to(T0 + 10 * MS)
        with pytest.raises(ValueError, match="time goes back"):
            run.advance_to(T0)


def test_a_wall_clock_read_in_a_callback_is_reported_once_per_line() -> None:
    with DeterministicRun(T0) as run:
        node = run.add_node(Node, name="reader")
        node.create_subscription(Int32, "/in", lambda m: time.time())
        for i in range(3):
            run.deliver("/in", Int32(data=i), T0 + i * MS)
        reads = list(run.check.reads)
        assert run.check.count == 3
        assert len(reads) == 1 and reads[0][0] == "time.time"
        assert reads[0][1] == __file__
    assert time.time.__module__ == "time"  # unwrapped after the dispatch


def test_an_exempt_caller_and_a_run_without_the_check_report_nothing() -> None:
    with DeterministicRun(T0, exempt={"/unit/replay/": "this test"}) as run:
        node = run.add_node(Node, name="reader")
        node.create_subscription(Int32, "/in", lambda m: time.monotonic())
        run.deliver("/in", Int32(data=1), T0 + MS)
        assert run.check.reads == []
    with DeterministicRun(T0, check=False) as run:
        node = run.add_node(Node, name="reader")
        node.create_subscription(Int32, "/in", lambda m: time.monotonic())
        run.deliver("/in", Int32(data=1), T0 + MS)
        assert run.check.count == 0


def test_random_is_seeded_at_the_start_of_a_run() -> None:
    with DeterministicRun(T0):
        first = random.random()
    with DeterministicRun(T0):
        assert random.random() == first


def test_async_callbacks_run_before_the_next_step() -> None:
    seen: list[int] = []

    class Async(Node):
        def setup(self) -> None:
            async def on_msg(m: Int32) -> None:
                seen.append(m.data)

            self.create_subscription(Int32, "/in", on_msg)

    with DeterministicRun(T0) as run:
        run.add_node(Async)
        run.deliver("/in", Int32(data=7), T0 + MS)
        assert seen == [7]
