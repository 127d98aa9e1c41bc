"""Keyboard controls for ``zenros bag play`` on a terminal: space pauses/resumes, ``s`` steps."""

from __future__ import annotations

import os
import select
import sys
import threading
from collections.abc import Callable
from contextlib import AbstractContextManager, nullcontext
from typing import Any, Self

__all__ = ["keyboard_controls"]


class _Keys(AbstractContextManager["_Keys"]):
    def __init__(self, handlers: dict[str, Callable[[], None]]) -> None:
        import termios

        self._handlers = handlers
        self._fd = sys.stdin.fileno()
        self._old: Any = termios.tcgetattr(self._fd)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, daemon=True, name="zenros-bag-keys")

    def __enter__(self) -> Self:
        import termios
        import tty

        tty.setcbreak(self._fd, termios.TCSANOW)
        self._thread.start()
        return self

    def _loop(self) -> None:
        while not self._stop.is_set():
            ready, _, _ = select.select([self._fd], [], [], 0.1)
            if not ready:
                continue
            ch = os.read(self._fd, 1).decode(errors="replace")
            fn = self._handlers.get(ch)
            if fn is not None:
                fn()

    def __exit__(self, *exc: object) -> None:
        import termios

        self._stop.set()
        self._thread.join(1.0)
        termios.tcsetattr(self._fd, termios.TCSADRAIN, self._old)


def keyboard_controls(handlers: dict[str, Callable[[], None]]) -> AbstractContextManager[Any]:
    """Call ``handlers[key]`` on each key press while active; nothing when stdin is no tty."""
    try:
        if sys.stdin is None or not sys.stdin.isatty():
            return nullcontext()
        return _Keys(handlers)
    except (OSError, ValueError, ImportError):
        return nullcontext()
