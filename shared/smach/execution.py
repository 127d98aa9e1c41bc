"""`Execution`: a container running on a background thread, as a future you can preempt."""

from __future__ import annotations

import asyncio
import concurrent.futures
import threading
from collections.abc import Callable, Generator
from typing import Any

from ..errors import ZenrosTimeout
from .parent import Parent
from .userdata import UserDataAccess

__all__ = ["Execution"]


class Execution:
    """One background run of a container; made by `Container.execute_in_thread`.

    The outcome (or the exception `execute` raised) lands in `future`, a
    `concurrent.futures.Future`; ``await execution`` waits for it from asyncio code
    without blocking the event loop. `request_preempt` may be called from any thread.
    The thread is a daemon: preempt and wait for the run before the program exits.
    """

    def __init__(self, container: Parent, userdata: UserDataAccess | None) -> None:
        self.container = container
        self.future: concurrent.futures.Future[str] = concurrent.futures.Future()
        self._thread = threading.Thread(
            target=self._run,
            args=(userdata,),
            name=f"smach:{container.path}",
            daemon=True,
        )
        self._thread.start()

    def _run(self, userdata: UserDataAccess | None) -> None:
        self.future.set_running_or_notify_cancel()
        try:
            outcome = self.container._run_claimed(userdata)
        except Exception as exc:  # noqa: BLE001  (handed to whoever waits on the future)
            self.future.set_exception(exc)
        else:
            self.future.set_result(outcome)

    def request_preempt(self) -> None:
        """Ask the running container to stop early (cooperative; see `State.request_preempt`)."""
        self.container.request_preempt()

    def done(self) -> bool:
        """True once the run has ended, with an outcome or an exception."""
        return self.future.done()

    def result(self, timeout: float | None = None) -> str:
        """Wait for the outcome.

        Args:
            timeout: Seconds to wait; None waits for ever.

        Raises:
            ZenrosTimeout: The run did not end within ``timeout``.
            Exception: Whatever `Container.execute` raised.
        """
        try:
            return self.future.result(timeout)
        except concurrent.futures.TimeoutError:
            raise ZenrosTimeout(
                f"{self.container.describe()} did not finish within {timeout} s;"
                f" active: {self.container.get_active_states()}"
            ) from None

    def add_done_callback(self, fn: Callable[[Execution], Any]) -> None:
        """Call ``fn(self)`` when the run ends (at once if it already has)."""
        self.future.add_done_callback(lambda _f: fn(self))

    def join(self, timeout: float | None = None) -> bool:
        """Wait for the thread to end; True if it did within ``timeout``."""
        self._thread.join(timeout)
        return not self._thread.is_alive()

    def __await__(self) -> Generator[Any, None, str]:
        return asyncio.wrap_future(self.future).__await__()

    def __repr__(self) -> str:
        state = "done" if self.done() else "running"
        return f"<Execution {self.container.describe()} {state}>"
