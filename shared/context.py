"""A `Context`: one Zenoh session, its executor, key space, in-process bus and graph view.

Nodes created in the same context share the session; messages between them skip
serialization (intra-process delivery), while other processes still get them over Zenoh.
"""

from __future__ import annotations

import itertools
import threading
from typing import TYPE_CHECKING, Any, Self

import zenoh

from .executor import Executor
from .names import KeySpace
from .session import SessionOptions, open_session

if TYPE_CHECKING:
    from .graph import Graph

__all__ = ["Context", "LocalTopic"]


class LocalTopic:
    """In-process endpoints of one topic; publishers read ``subs`` without locking."""

    __slots__ = ("subs",)

    def __init__(self) -> None:
        self.subs: tuple[Any, ...] = ()


class Context:
    """Owns a Zenoh session and what every node on it shares."""

    def __init__(
        self,
        options: SessionOptions | zenoh.Config | None = None,
        *,
        prefix: str | None = None,
        session: zenoh.Session | None = None,
    ) -> None:
        self.keys = KeySpace.from_env(prefix)
        self.session = session if session is not None else open_session(options or SessionOptions())
        self._own_session = session is None
        self.zid = str(self.session.zid())
        self.executor = Executor()
        self._lock = threading.Lock()
        self._topics: dict[str, LocalTopic] = {}
        self._graph: Graph | None = None
        self._eids = itertools.count(1)
        self._closables: list[Any] = []
        self.closed = False

    def next_eid(self) -> int:
        return next(self._eids)

    def local_topic(self, fqn: str) -> LocalTopic:
        with self._lock:
            topic = self._topics.get(fqn)
            if topic is None:
                topic = self._topics[fqn] = LocalTopic()
            return topic

    def add_local(self, fqn: str, attr: str, endpoint: Any) -> LocalTopic:
        topic = self.local_topic(fqn)
        with self._lock:
            setattr(topic, attr, getattr(topic, attr) + (endpoint,))
        return topic

    def remove_local(self, fqn: str, attr: str, endpoint: Any) -> None:
        topic = self.local_topic(fqn)
        with self._lock:
            setattr(topic, attr, tuple(e for e in getattr(topic, attr) if e is not endpoint))

    @property
    def graph(self) -> Graph:
        """The live graph view (created on first use, shared by the context's nodes)."""
        with self._lock:
            if self._graph is None:
                from .graph import Graph

                self._graph = Graph(self.session, self.keys)
            return self._graph

    def close(self) -> None:
        """Close the graph, stop the executor and close the session (if we opened it)."""
        if self.closed:
            return
        self.closed = True
        if self._graph is not None:
            self._graph.close()
        self.executor.stop()
        if self._own_session:
            self.session.close()  # type: ignore[no-untyped-call]

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
