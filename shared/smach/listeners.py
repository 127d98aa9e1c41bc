"""`ListenerSet`: the callbacks registered on a container's events."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

from .introspection import ContainerEvent, Listener

__all__ = ["ListenerSet"]

log = logging.getLogger(__name__)


class ListenerSet:
    """A thread-safe list of event listeners; one failing listener does not stop the rest."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._listeners: list[Listener] = []

    def add(self, listener: Listener) -> Callable[[], None]:
        """Register ``listener``; returns a function that removes it again."""
        with self._lock:
            self._listeners.append(listener)

        def remove() -> None:
            with self._lock:
                if listener in self._listeners:
                    self._listeners.remove(listener)

        return remove

    def dispatch(self, event: ContainerEvent) -> None:
        """Call every listener with ``event``; log, and otherwise ignore, their exceptions."""
        with self._lock:
            listeners = list(self._listeners)
        for listener in listeners:
            try:
                listener(event)
            except Exception:  # an observer must not break the machine it observes
                log.exception(
                    "smach listener %r failed on the %s event of %s", listener, event.kind, event.path
                )
