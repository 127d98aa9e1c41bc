"""`ApproximateTimeSynchronizer`: ROS's ApproximateTime policy.

The policy (wiki.ros.org/message_filters/ApproximateTime, and ROS 2's
sync_policies/approximate_time): every message is used at most once, the sets it emits never
cross and leave no message out between theirs, each is the set of smallest span among the
messages it could still wait for, and the choice depends on the stamps alone (not on arrival
order across topics). It works on a per-topic queue; the topic whose message ends the best set
so far is the pivot, and a set is emitted once no later message can beat it: when its pivot's
message has been passed, or when the spread of what is queued, or of what the per-topic
inter-message lower bounds say could still come, already exceeds the candidate's. An age
penalty favours emitting sooner over a set later by a little.
"""

from __future__ import annotations

import logging
import math
import threading
from collections import deque
from collections.abc import Sequence
from typing import Any

from ..clock import Clock
from .exact import connect_inputs
from .filter import SimpleFilter, clock_of, stamp_ns

__all__ = ["ApproximateTimeSynchronizer"]

log = logging.getLogger("zenros.message_filters")

_NS = 1_000_000_000
Item = tuple[int, Any]  # (stamp in ns, message)


class ApproximateTimeSynchronizer(SimpleFilter):
    """rclpy's ``ApproximateTimeSynchronizer(fs, queue_size, slop, allow_headerless=False)``
    with the ApproximateTime policy of ROS's C++ message_filters.

    Args:
        fs: the input filters (at least 2); input ``i``'s messages come from ``fs[i]``.
        queue_size: messages kept per topic (ROS's queue_size, counting those already passed
            over while a candidate set waits).
        slop: the largest span (seconds, last stamp minus first) of an emitted set: the
            policy's max_interval_duration; ``math.inf`` for no bound.
        allow_headerless: stamp messages without ``header.stamp`` with the clock's now
            (the input node's clock, or ``clock``); otherwise they are dropped with a warning.
        age_penalty: ROS's (default 0.1): how much a later set must be tighter to win.
        inter_message_lower_bounds: per input, the least time (seconds) between two of its
            messages, which lets a set be emitted before the next message proves it best.
    """

    def __init__(self, fs: Sequence[SimpleFilter], queue_size: int, slop: float = math.inf,
                 allow_headerless: bool = False, *, age_penalty: float = 0.1,
                 inter_message_lower_bounds: Sequence[float] | None = None,
                 clock: Clock | None = None) -> None:
        super().__init__()
        n = len(fs)
        if n < 2:
            raise ValueError(f"a synchronizer needs at least 2 inputs, got {n}")
        if queue_size < 1:
            raise ValueError(f"queue_size must be at least 1, got {queue_size}")
        if not slop >= 0:
            raise ValueError(f"slop must be >= 0 seconds, got {slop}")
        if not age_penalty >= 0:
            raise ValueError(f"age_penalty must be >= 0, got {age_penalty}")
        bounds = list(inter_message_lower_bounds or [0.0] * n)
        if len(bounds) != n or any(not b >= 0 for b in bounds):
            raise ValueError(f"inter_message_lower_bounds: {n} values >= 0 expected, got {bounds}")
        self.n_inputs = n
        self.queue_size = queue_size
        self.slop = slop
        self.allow_headerless = allow_headerless
        self._max_interval = None if math.isinf(slop) else round(slop * _NS)
        self._factor = 1.0 + age_penalty
        self._bounds = [round(b * _NS) for b in bounds]
        self._clock = clock
        self._lock = threading.Lock()
        self._deques: list[deque[Item]] = [deque() for _ in range(n)]
        self._past: list[list[Item]] = [[] for _ in range(n)]
        self._non_empty = 0
        self._dropped = [False] * n
        self._candidate: list[Any] | None = None
        self._cand_start = self._cand_end = 0
        self._pivot = -1
        self._pivot_time = 0
        self._last = [None] * n  # type: list[int | None]
        self._warned = [False] * n
        self._out: list[list[Any]] = []
        if fs:
            self._clock = clock_of(fs[0], clock)
        connect_inputs(self, fs)

    def connectInput(self, fs: Sequence[SimpleFilter]) -> None:
        connect_inputs(self, fs)

    def add(self, msg: Any, index: int) -> None:
        """Input ``index`` received ``msg``; signals the sets this completes."""
        t = stamp_ns(msg)
        if t is None:
            if not self.allow_headerless:
                log.warning("ApproximateTimeSynchronizer: dropping %s, which has no "
                            "header.stamp (allow_headerless=True stamps it with now)",
                            type(msg).__name__)
                return
            t = clock_of(None, self._clock).now().nanoseconds
        if not 0 <= index < self.n_inputs:
            raise IndexError(f"input {index} of a {self.n_inputs}-input synchronizer")
        with self._lock:
            self._add(index, t, msg)
            out, self._out = self._out, []
        for msgs in out:
            self.signalMessage(*msgs)

    # ------------------------------------------------------------ the policy (lock held)

    def _add(self, i: int, t: int, msg: Any) -> None:
        q = self._deques[i]
        q.append((t, msg))
        self._check_bound(i, t)
        if len(q) == 1:
            self._non_empty += 1
            if self._non_empty == self.n_inputs:
                self._process()
        if len(q) + len(self._past[i]) > self.queue_size:
            # cancel the candidate search, drop this topic's oldest, and look again
            self._non_empty = 0
            for k in range(self.n_inputs):
                self._recover(k, len(self._past[k]))
            q.popleft()
            self._dropped[i] = True
            if self._pivot >= 0:
                self._candidate = None
                self._pivot = -1
                self._process()

    def _check_bound(self, i: int, t: int) -> None:
        last, self._last[i] = self._last[i], t
        if last is None or self._warned[i] or t - last >= self._bounds[i]:
            return
        if t < last:
            self._warned[i] = True
            log.warning("ApproximateTimeSynchronizer: input %d went back in time (%d ns after "
                        "%d ns); sets may be missed", i, t, last)
        elif t - last < self._bounds[i]:
            self._warned[i] = True
            log.warning("ApproximateTimeSynchronizer: input %d: messages %d ns apart, closer "
                        "than its inter-message lower bound (%d ns)", i, t - last,
                        self._bounds[i])

    def _pop_front(self, i: int) -> None:
        q = self._deques[i]
        q.popleft()
        if not q:
            self._non_empty -= 1

    def _front_to_past(self, i: int) -> None:
        q = self._deques[i]
        self._past[i].append(q.popleft())
        if not q:
            self._non_empty -= 1

    def _recover(self, i: int, count: int) -> None:
        q, past = self._deques[i], self._past[i]
        if count:
            q.extendleft(reversed(past[-count:]))
            del past[-count:]
        if q:
            self._non_empty += 1

    def _make_candidate(self) -> None:
        self._candidate = [q[0][1] for q in self._deques]
        for past in self._past:
            past.clear()

    def _publish(self) -> None:
        assert self._candidate is not None
        self._out.append(self._candidate)
        self._candidate = None
        self._pivot = -1
        non_empty = 0
        for q, past in zip(self._deques, self._past):
            if past:
                q.extendleft(reversed(past))
                past.clear()
            q.popleft()  # the message the candidate used
            if q:
                non_empty += 1
        self._non_empty = non_empty

    def _bounds_of(self, times: Sequence[int]) -> tuple[int, int, int, int]:
        """(start index, start time, end index, end time); ties: the first input starts,
        the last one ends (ROS's order)."""
        si = ei = 0
        st = et = times[0]
        for k in range(1, len(times)):
            tk = times[k]
            if tk < st:
                si, st = k, tk
            if tk >= et:
                ei, et = k, tk
        return si, st, ei, et

    def _worse(self, end: int, start: int) -> bool:
        """The set ending at ``end`` and starting at ``start`` is no better than the
        candidate: (end - candidate end) * (1 + age penalty) >= start - candidate start."""
        return int((end - self._cand_end) * self._factor) >= start - self._cand_start

    def _virtual_time(self, i: int) -> int:
        q = self._deques[i]
        if q:
            return q[0][0]
        return max(self._pivot_time, self._past[i][-1][0] + self._bounds[i])

    def _process(self) -> None:
        n = self.n_inputs
        while self._non_empty == n:
            si, st, ei, et = self._bounds_of([q[0][0] for q in self._deques])
            for k in range(n):
                if k != ei:
                    self._dropped[k] = False
            if self._pivot < 0:
                if (self._max_interval is not None and et - st > self._max_interval) \
                        or self._dropped[ei]:
                    self._pop_front(si)
                    continue
                self._make_candidate()
                self._cand_start, self._cand_end = st, et
                self._pivot, self._pivot_time = ei, et
                self._front_to_past(si)
            else:
                if not self._worse(et, st):
                    self._make_candidate()
                    self._cand_start, self._cand_end = st, et
                self._front_to_past(si)
            if si == self._pivot:
                self._publish()  # every set with this pivot has been seen
            elif self._worse(et, self._pivot_time):
                self._publish()  # any later set spans [pivot time, end]: already worse
            elif self._non_empty < n:
                self._virtual_search()

    def _virtual_search(self) -> None:
        """Try to prove the candidate best with what the lower bounds say could still come."""
        moves = [0] * self.n_inputs
        while True:
            si, st, _ei, et = self._bounds_of(
                [self._virtual_time(k) for k in range(self.n_inputs)])
            if self._worse(et, self._pivot_time):
                self._publish()
                return
            if not self._worse(et, st):
                # an optimistic future set beats the candidate: wait, undo the moves
                self._non_empty = 0
                for k in range(self.n_inputs):
                    self._recover(k, moves[k])
                return
            self._front_to_past(si)
            moves[si] += 1
