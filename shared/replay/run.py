"""`DeterministicRun`: nodes composed in one process on a clock the caller moves, with every
message and timer dispatched in a defined order on the caller's thread.

The order, for each input message at time t (a bag's log time):

1. every timer due at or before t fires at its exact deadline, earliest first; timers due
   at the same instant fire in the order they started waiting (the order their nodes
   created them, at the start);
2. the clock is set to t and the message is handed to each subscription of the run's nodes
   on its topic, in the order they were created; each callback runs to completion, and so
   does whatever it publishes to another node of the run (depth first);
3. ``async def`` callbacks and work queued on the executor run before the next step.

Timers therefore come before messages of the same instant. Outputs (every publish of the
run's nodes) go to ``on_output(topic, msg, time_ns)`` as they happen.
"""

from __future__ import annotations

import logging
import random
from collections.abc import Callable
from contextlib import nullcontext
from typing import Any, Self

import numpy as np

from ..clock import Time
from ..node import Node
from .context import OutputTap, ReplayContext
from .walltime import WallClockCheck

__all__ = ["DeterministicRun", "OutputCallback"]

OutputCallback = Callable[[str, Any, int], None]
SEED = 0  # what `random` and numpy's global generator are seeded with at the start of a run


class _BagSender:
    """Stands in for the publisher of an input message (named in type-mismatch errors)."""

    def __init__(self, topic: str, type_name: str) -> None:
        self.topic, self.type_name = topic, type_name


class DeterministicRun:
    """Owns a `ReplayContext`, its nodes and its clock; the caller feeds it messages.

    Args:
        start_ns: the simulated time at which the nodes are created.
        on_output: called with (topic, message, simulated ns) for each publish of a node.
        check: report wall-clock reads and unseeded randomness inside callbacks (timers and
            deliveries; not the nodes' setup and close) with `WallClockCheck`.
        exempt: callers the check ignores (path fragment: why), `WallClockCheck`.
    """

    def __init__(self, start_ns: int, on_output: OutputCallback | None = None, *,
                 check: bool = True, logger: logging.Logger | None = None,
                 exempt: dict[str, str] | None = None) -> None:
        self._on_output = on_output
        self.outputs = 0
        self.delivered = 0
        self.timer_steps = 0
        self.published_topics: set[str] = set()
        self.ctx = ReplayContext(Time.from_nanoseconds(start_ns), OutputTap(self._output))
        self.clock = self.ctx.clock
        self.executor = self.ctx.stepper
        self.check = WallClockCheck(logger or logging.getLogger("zenros.replay"), exempt)
        self._checking = check
        if check:
            self.check.install()
        self.nodes: list[Node] = []
        random.seed(SEED)
        np.random.seed(SEED)

    @property
    def now_ns(self) -> int:
        return self.clock.now().nanoseconds

    def _watch(self) -> Any:
        return self.check.watching() if self._checking else nullcontext()

    def add_node(self, factory: Callable[..., Node], **kwargs: Any) -> Node:
        """Create a node on the run's context (``factory(context=..., **kwargs)``) and run
        what its setup queued; its publishers' topics become outputs, never inputs."""
        node = factory(context=self.ctx, **kwargs)
        self.executor.drain()
        self.nodes.append(node)
        for ep in node._endpoints:
            topic = getattr(ep, "topic", None)
            if topic is not None and hasattr(ep, "publish"):
                self.published_topics.add(topic)
        return node

    def subscribed(self, topic: str) -> bool:
        """Whether a node of the run takes ``topic`` as an input."""
        return bool(self.ctx.subscribers(topic)) and topic not in self.published_topics

    def advance_to(self, t_ns: int) -> None:
        """Fire every timer due up to ``t_ns`` at its deadline, then set the clock to it."""
        if t_ns < self.now_ns:
            raise ValueError(f"time goes back: {t_ns} < {self.now_ns} ns (inputs must be in "
                             "log-time order)")
        clock, drain = self.clock, self.executor.drain
        with self._watch():
            while True:
                due = clock.next_due()
                if due is None or due > t_ns:
                    break
                clock.set(Time.from_nanoseconds(max(due, self.now_ns)))
                drain()
                self.timer_steps += 1
            clock.set(Time.from_nanoseconds(t_ns))
            drain()

    def deliver(self, topic: str, msg: Any, t_ns: int, type_name: str = "") -> int:
        """Advance to ``t_ns`` and hand ``msg`` to the run's subscriptions on ``topic``;
        returns how many took it (0 for a topic no node takes or a node publishes)."""
        self.advance_to(t_ns)
        if topic in self.published_topics:
            return 0
        subs = self.ctx.subscribers(topic)
        if not subs:
            return 0
        sender = _BagSender(topic, type_name or type(msg).__name__)
        with self._watch():
            for sub in subs:
                sub._deliver_local(msg, sender)
            self.executor.drain()
        self.delivered += 1
        return len(subs)

    def _output(self, topic: str, msg: Any) -> None:
        self.published_topics.add(topic)
        self.outputs += 1
        if self._on_output is not None:
            self._on_output(topic, msg, self.now_ns)

    def close(self) -> None:
        """Close the nodes (last first), then the context."""
        for node in reversed(self.nodes):
            node.close()
        self.nodes.clear()
        self.ctx.close()
        self.check.uninstall()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
