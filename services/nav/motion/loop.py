"""ControlLoop: calls ``step()`` every ``period`` seconds of a clock, on a thread of its own.

The control step must not queue behind other timers (costmap publishing, status), so it
gets its own thread, sleeping on the node's clock (simulated time follows ``/clock``).
When a step overruns, the missed deadlines are skipped, as timers do. A wall-clock
``timeout`` on each sleep lets the loop notice `stop` even while sim time stands still.

With ``idle`` given, the loop does not tick while ``idle()`` is true (nothing to drive): it
sleeps until `wake` (a goal started, a behaviour halted) or ``idle_period`` wall seconds
have passed (a slow step for what a step checks besides driving, e.g. auto-charging), and
then steps at once. A robot at rest thus costs no control ticks (docs/fleet.md).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

from zenros.clock import Clock, Duration

__all__ = ["ControlLoop"]


class ControlLoop:
    def __init__(self, clock: Clock, period: float, step: Callable[[], None],
                 logger: logging.Logger, name: str = "nav-control",
                 idle: Callable[[], bool] | None = None, idle_period: float = 1.0) -> None:
        if not period > 0:
            raise ValueError(f"control period must be positive, got {period}")
        self.clock, self.step, self.logger = clock, step, logger
        self.period = Duration.from_seconds(period)
        self.idle, self.idle_period = idle, idle_period
        self.calls = 0
        self._stop = threading.Event()
        self._wake = threading.Event()
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _run(self) -> None:
        due = self.clock.now() + self.period
        while not self._stop.is_set():
            if self.idle is not None and self.idle():
                self._wake.wait(self.idle_period)
                self._wake.clear()  # a wake after this is seen by idle() below: none is lost
                due = self.clock.now()
            elif not self.clock.sleep_until(due, timeout=0.2):
                continue  # the clock has not reached the deadline yet (or sim time paused)
            if self._stop.is_set():
                return
            self.calls += 1
            try:
                self.step()
            except Exception:  # a failed step must not stop the robot's loop
                self.logger.exception("control step failed")
            now = self.clock.now()
            due = due + self.period
            if now >= due:  # overran, or the clock jumped: skip the missed deadlines
                behind = (now - due).nanoseconds // self.period.nanoseconds + 1
                due = due + self.period * behind
            elif (due - now).nanoseconds > 2 * self.period.nanoseconds:
                due = now + self.period  # the clock went back (a sim restart)

    def wake(self) -> None:
        """Step now if idle (a goal started or a behaviour ended); harmless otherwise."""
        self._wake.set()

    def stop(self) -> None:
        self._stop.set()
        self._wake.set()
        if self._thread.is_alive() and self._thread is not threading.current_thread():
            self._thread.join(2.0)
