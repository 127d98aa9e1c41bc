"""`ReplayContext`: a `Context` whose nodes run on a simulated clock and a stepped executor,
and whose every publish is also handed to the run's output tap."""

from __future__ import annotations

import uuid
from collections.abc import Callable
from typing import Any

from ..clock import Time
from ..context import Context, LocalTopic
from ..session import SessionOptions
from .clock import ReplayClock
from .executor import DeterministicExecutor

__all__ = ["OutputTap", "ReplayContext"]


class OutputTap:
    """Sits on every topic of the context's in-process bus as one more subscriber: whatever
    a node publishes comes here too, synchronously, in the order it was published."""

    def __init__(self, on_output: Callable[[str, Any], None]) -> None:
        self.on_output = on_output

    def _deliver_local(self, msg: Any, pub: Any) -> None:
        self.on_output(pub.topic, msg)


class ReplayContext(Context):
    """A context for deterministic runs (`zenros.replay.DeterministicRun`).

    Its Zenoh session is private: a peer on a key prefix of its own that connects to nothing
    (services and action servers still declare their queryables there, and nothing calls
    them). Messages reach its nodes only by the run's direct dispatch and by the in-process
    bus between its nodes; every timer and node clock is the run's `ReplayClock`.
    """

    deterministic = True

    def __init__(self, start: Time, tap: OutputTap) -> None:
        super().__init__(SessionOptions(mode="peer", connect=[]), prefix="zr" + uuid.uuid4().hex[:10])
        self.executor.stop()  # the threaded one Context made: replaced by a stepped one
        self.stepper = self.executor = DeterministicExecutor()
        self.sim_clock = self.clock = ReplayClock(start)
        self.clock.active = True
        self.tap = tap

    def local_topic(self, fqn: str) -> LocalTopic:
        with self._lock:
            topic = self._topics.get(fqn)
            if topic is None:
                topic = self._topics[fqn] = LocalTopic()
                topic.subs = (self.tap,)
            return topic

    def subscribers(self, fqn: str) -> tuple[Any, ...]:
        """The subscriptions of the context's nodes on ``fqn`` (not the tap)."""
        return tuple(s for s in self.local_topic(fqn).subs if s is not self.tap)
