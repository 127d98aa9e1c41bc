"""The standard diagnostic tasks: `FrequencyStatus` (event rate) and `TimeStampStatus`
(stamp delays), as diagnostic_updater's."""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any

from ..clock import Clock, SystemClock
from ..msgs.builtin_interfaces import Time
from .status import ERROR, OK, WARN, DiagnosticStatusWrapper
from .updater import DiagnosticTask

__all__ = ["FrequencyStatus", "FrequencyStatusParam", "TimeStampStatus", "TimeStampStatusParam"]


@dataclass
class FrequencyStatusParam:
    """``freq_bound``: ``{'min': Hz, 'max': Hz}`` (either may be left out); ``tolerance``:
    the fraction beyond them still accepted; ``window_size``: updates the rate is taken over."""

    freq_bound: dict[str, float] = field(default_factory=dict)
    tolerance: float = 0.1
    window_size: int = 5

    def __post_init__(self) -> None:
        if self.window_size < 1:
            raise ValueError(f"window_size must be at least 1, got {self.window_size}")
        if set(self.freq_bound) - {"min", "max"}:
            raise ValueError(f"freq_bound keys are 'min' and 'max', got {sorted(self.freq_bound)}")


class FrequencyStatus(DiagnosticTask):
    """Counts ``tick()``s; each run reports the rate over the last ``window_size`` runs:
    ERROR "No events recorded." for none, WARN "Frequency too low." / "Frequency too
    high." outside the bounds (with the tolerance), else OK "Desired frequency met"."""

    def __init__(self, params: FrequencyStatusParam, name: str = "FrequencyStatus", *,
                 clock: Clock | None = None) -> None:
        super().__init__(name)
        self.params = params
        self._clock = clock or SystemClock()
        self._lock = threading.Lock()
        self.clear()

    def clear(self) -> None:
        with self._lock:
            now = self._clock.now().nanoseconds
            self.count = 0
            self._times = [now] * self.params.window_size
            self._seqs = [0] * self.params.window_size
            self._k = 0

    def tick(self) -> None:
        with self._lock:
            self.count += 1

    def run(self, stat: DiagnosticStatusWrapper) -> DiagnosticStatusWrapper:
        p = self.params
        lo, hi = p.freq_bound.get("min"), p.freq_bound.get("max")
        with self._lock:
            now = self._clock.now().nanoseconds
            events = self.count - self._seqs[self._k]
            window = (now - self._times[self._k]) / 1e9
            freq = events / window if window > 0 else 0.0
            self._seqs[self._k], self._times[self._k] = self.count, now
            self._k = (self._k + 1) % p.window_size
            count = self.count
        if events == 0:
            stat.summary(ERROR, "No events recorded.")
        elif lo is not None and freq < lo * (1 - p.tolerance):
            stat.summary(WARN, "Frequency too low.")
        elif hi is not None and freq > hi * (1 + p.tolerance):
            stat.summary(WARN, "Frequency too high.")
        else:
            stat.summary(OK, "Desired frequency met")
        stat.add("Events in window", events)
        stat.add("Events since startup", count)
        stat.add("Duration of window (s)", f"{window:f}")
        stat.add("Actual frequency (Hz)", f"{freq:f}")
        if lo is not None and lo == hi:
            stat.add("Target frequency (Hz)", f"{lo:f}")
        if lo is not None and lo > 0:
            stat.add("Minimum acceptable frequency (Hz)", f"{lo * (1 - p.tolerance):f}")
        if hi is not None:
            stat.add("Maximum acceptable frequency (Hz)", f"{hi * (1 + p.tolerance):f}")
        return stat


@dataclass
class TimeStampStatusParam:
    """Acceptable delays (s) of a stamp behind now: ``min_acceptable`` (negative: that far
    in the future) to ``max_acceptable``."""

    min_acceptable: float = -1.0
    max_acceptable: float = 5.0


class TimeStampStatus(DiagnosticTask):
    """``tick(stamp)`` per message; each run reports the delays (now - stamp) seen since the
    last: ERROR "Timestamps too far in future seen." / "Timestamps too far in past seen." /
    "Zero timestamp seen.", WARN "No data since last update.", else OK "Timestamps are
    reasonable."."""

    def __init__(self, params: TimeStampStatusParam | None = None,
                 name: str = "Timestamp Status", *, clock: Clock | None = None) -> None:
        super().__init__(name)
        self.params = params or TimeStampStatusParam()
        self._clock = clock or SystemClock()
        self._lock = threading.Lock()
        self.early_count = self.late_count = self.zero_count = 0
        self._reset()

    def _reset(self) -> None:
        self.zero_seen = False
        self.max_delta = self.min_delta = 0.0
        self.deltas_valid = False

    def tick(self, stamp: Time | float | Any) -> None:
        """A message stamped ``stamp`` (a `Time`, anything with ``nanoseconds``, or seconds)."""
        ns = getattr(stamp, "nanoseconds", None)
        if isinstance(ns, int):
            secs = ns / 1e9
        elif isinstance(stamp, (int, float)) and not isinstance(stamp, bool):
            secs = float(stamp)
        else:
            raise TypeError(f"tick: a Time or seconds, got {type(stamp).__name__}")
        with self._lock:
            if secs == 0:
                self.zero_seen = True
                return
            delta = self._clock.now().nanoseconds / 1e9 - secs
            if not self.deltas_valid or delta > self.max_delta:
                self.max_delta = delta
            if not self.deltas_valid or delta < self.min_delta:
                self.min_delta = delta
            self.deltas_valid = True

    def run(self, stat: DiagnosticStatusWrapper) -> DiagnosticStatusWrapper:
        p = self.params
        with self._lock:
            stat.summary(OK, "Timestamps are reasonable.")
            if not self.deltas_valid:
                stat.summary(WARN, "No data since last update.")
            else:
                if self.min_delta < p.min_acceptable:
                    stat.summary(ERROR, "Timestamps too far in future seen.")
                    self.early_count += 1
                if self.max_delta > p.max_acceptable:
                    stat.summary(ERROR, "Timestamps too far in past seen.")
                    self.late_count += 1
            if self.zero_seen:
                stat.summary(ERROR, "Zero timestamp seen.")
                self.zero_count += 1
            stat.add("Earliest timestamp delay:", f"{self.min_delta:f}")
            stat.add("Latest timestamp delay:", f"{self.max_delta:f}")
            stat.add("Earliest acceptable timestamp delay:", f"{p.min_acceptable:f}")
            stat.add("Latest acceptable timestamp delay:", f"{p.max_acceptable:f}")
            stat.add("Late diagnostic update count:", self.late_count)
            stat.add("Early diagnostic update count:", self.early_count)
            stat.add("Zero seen diagnostic count:", self.zero_count)
            self._reset()
        return stat
