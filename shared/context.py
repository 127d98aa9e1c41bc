"""A `Context`: one Zenoh session, its executor, key space, in-process bus and graph view.

Nodes created in the same context share the session; messages between them skip
serialization (intra-process delivery), while other processes still get them over Zenoh.
"""

from __future__ import annotations

import itertools
import logging
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Self

import zenoh

from .executor import Executor
from .names import KeySpace
from .session import SessionOptions, open_session

if TYPE_CHECKING:
    from .clock import Clock
    from .graph import Graph

__all__ = ["Context", "LocalTopic", "is_session_failure"]

_log = logging.getLogger("zenros.context")


def is_session_failure(exc: BaseException) -> bool:
    """True for the error a Zenoh call raises once its session is broken for good.

    zenoh-python turns a panic of the Rust library into ``pyo3_runtime.PanicException`` (a
    BaseException). After one, the session's transport is poisoned: every later call that
    sends panics too, so the session cannot recover in this process.
    """
    return type(exc).__name__ == "PanicException"


class LocalTopic:
    """In-process endpoints of one topic; publishers read ``subs`` without locking."""

    __slots__ = ("subs",)

    def __init__(self) -> None:
        self.subs: tuple[Any, ...] = ()


class Context:
    """Owns a Zenoh session and what every node on it shares.

    ``sim_clock``: set by a deterministic run (`zenros.replay`), every node of the context
    runs on it (``use_sim_time`` or not) and so does every timer; ``deterministic`` tells
    nodes that they must not start threads of their own (docs/replay.md)."""

    deterministic: bool = False
    sim_clock: Clock | None = None

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
        self._served: dict[str, int] = {}  # request keys a queryable of this session serves
        self._closables: list[Any] = []
        self._on_failure: list[Callable[[BaseException], None]] = []
        self.failure: BaseException | None = None
        self.closed = False

    def next_eid(self) -> int:
        return next(self._eids)

    def serve_here(self, *keys: str) -> Callable[[], None]:
        """Note that this session serves requests on ``keys`` (services, action requests);
        returns the function that takes the note back. See `destination`."""
        with self._lock:
            for k in keys:
                self._served[k] = self._served.get(k, 0) + 1

        def forget() -> None:
            with self._lock:
                for k in keys:
                    n = self._served.get(k, 0) - 1
                    if n > 0:
                        self._served[k] = n
                    else:
                        self._served.pop(k, None)

        return forget

    def destination(self, key: str) -> zenoh.Locality:
        """Where a request on ``key`` must go so that exactly one server runs it: this
        session's own server if it has one, else anywhere. Zenoh 1.10 delivers a
        BEST_MATCHING query to the session's own complete queryable *and* to a remote one
        (measured: every query), so a caller beside a server would run a non-idempotent
        request (a parameter delete, a goal) twice."""
        return zenoh.Locality.SESSION_LOCAL if key in self._served else zenoh.Locality.ANY

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

    # ------------------------------------------------------------------ failure

    def on_failure(self, callback: Callable[[BaseException], None]) -> None:
        """Call ``callback(exc)`` once if the session fails (see `fail`); the runtime uses
        it to end the process with a non-zero code, so that supervision restarts it."""
        with self._lock:
            failure = self.failure
            if failure is None:
                self._on_failure.append(callback)
        if failure is not None:
            callback(failure)

    def fail(self, exc: BaseException) -> None:
        """Record that the Zenoh session broke (`is_session_failure`): log it once and tell
        the `on_failure` callbacks. Receive loops call it when a Zenoh call panics."""
        with self._lock:
            if self.failure is not None:
                return
            self.failure = exc
            callbacks, self._on_failure = self._on_failure, []
        _log.critical("the Zenoh session failed (%s: %s); this process can no longer "
                      "communicate", type(exc).__name__, str(exc).splitlines()[0] if str(exc)
                      else "")
        for cb in callbacks:
            try:
                cb(exc)
            except Exception:  # noqa: BLE001 one callback must not keep the others from running
                _log.exception("session failure callback %r raised", cb)

    def close(self) -> None:
        """Close the graph, stop the executor and close the session (if we opened it).

        After a session failure the session is left alone: closing a poisoned session
        panics again (the process is about to exit anyway)."""
        if self.closed:
            return
        self.closed = True
        if self.failure is not None:
            self.executor.stop()
            return
        if self._graph is not None:
            self._graph.close()
        self.executor.stop()
        if self._own_session:
            try:
                self.session.close()  # type: ignore[no-untyped-call]
            except zenoh.ZError as exc:
                # Zenoh gives up closing after its own timeout (links flushed, peers told)
                # on a starved box; the work is done and the OS closes the sockets at exit,
                # so a CLI whose goal succeeded must not exit 1 over it.
                _log.warning("the Zenoh session did not close in time (%s); leaving it to "
                             "the process's exit", str(exc).split(" at ")[0])

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
