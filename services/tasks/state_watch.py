"""`StateWatch`: the latest state a chassis device publishes (a subscription's callback), and
a wait for the next one stamped after a given time, for the links that start a move with one
service call and follow it on the device's state topic (actuators, the PTZ camera)."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any, Final, Generic, Protocol, TypeVar

__all__ = ["POLL", "Silent", "StateWatch"]

POLL: Final = 0.02  # s between looks at ``cancelled``


class _Stamped(Protocol):
    header: Any


S = TypeVar("S", bound=_Stamped)


class Silent(Exception):
    """No state came for the watch's ``silence`` seconds: the device (its node) is gone."""


class StateWatch(Generic[S]):
    """Holds the newest state; `next_after` waits for one stamped after a time."""

    def __init__(self, silence: float) -> None:
        self.silence = silence
        self._cond = threading.Condition()
        self._state: S | None = None

    def __call__(self, msg: S) -> None:
        with self._cond:
            self._state = msg
            self._cond.notify_all()

    def next_after(self, since: Any, cancelled: Callable[[], bool]) -> S | None:
        """The newest state stamped after ``since`` (a `Time`); None once ``cancelled()``.

        Raises:
            Silent: none came for ``silence`` wall seconds.
        """
        deadline = time.monotonic() + self.silence
        with self._cond:
            while True:
                if cancelled():
                    return None
                state = self._state
                if state is not None and state.header.stamp > since:
                    return state
                if time.monotonic() > deadline:
                    raise Silent(f"nothing for {self.silence:g} s")
                self._cond.wait(POLL)
