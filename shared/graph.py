"""The computation graph, without a master: folded from Zenoh liveliness tokens."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import zenoh

from .names import KeySpace, Token

__all__ = ["Graph", "NodeInfo"]


@dataclass(frozen=True)
class NodeInfo:
    """What the graph knows about one node."""

    name: str
    zid: str
    host: str
    pid: int
    start_ns: int


Listener = Callable[[str, Token], None]


class Graph:
    """A live view of nodes, topics, services and actions; updated from liveliness events.

    A process that dies (kill -9) leaves the graph at once; a frozen one after the lease of
    its session (1 s by default in zenros), as Zenoh measures it.
    """

    def __init__(self, session: zenoh.Session, keys: KeySpace, *, snapshot_timeout: float = 2.0):
        self._keys = keys
        self._cond = threading.Condition()
        self._tokens: dict[str, Token] = {}
        self._deleted: set[str] = set()
        self._listeners: list[Listener] = []
        self._session = session
        self._changes = 0
        self._sub = session.liveliness().declare_subscriber(
            keys.alive_all(), self._on_sample, history=True
        )
        self._snapshot(snapshot_timeout)

    def _snapshot(self, timeout: float) -> None:
        # A callback, not the default FIFO channel: Zenoh 1.10 delivers the tokens it already
        # knows inside get(), holding the session's lock, and a channel that fills up (256
        # replies) before get() returns blocks that thread, and with it every Zenoh thread of
        # the process, for good (found with gdb in the two-robot demo: ~300 tokens).
        keys: list[str] = []
        done = threading.Event()

        def on_reply(reply: zenoh.Reply) -> None:
            if reply.ok is not None:
                keys.append(str(reply.ok.key_expr))

        self._session.liveliness().get(
            self._keys.alive_all(),
            zenoh.handlers.Callback(on_reply, done.set, indirect=False),
            timeout=timeout,
        )
        done.wait(timeout + 1.0)
        with self._cond:
            for key in list(keys):
                if key not in self._deleted and key not in self._tokens:
                    self._add(key)

    def settle(self, quiet: float = 0.3, timeout: float = 3.0) -> None:
        """Wait until the view stops changing for ``quiet`` seconds (at most ``timeout``).

        Tools that print one snapshot (``zenros node list``) call this: a fresh session
        learns the tokens of the network over its first few hundred milliseconds. An empty
        view is not taken as settled before ``timeout``: on a loaded box the first answers
        may come after ``quiet`` (a CLI once listed no node at all).
        """
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self._cond:
                before = self._changes
            self._snapshot(min(1.0, max(0.05, deadline - time.monotonic())))
            with self._cond:
                self._cond.wait_for(lambda b=before: self._changes != b,  # type: ignore[misc]
                                    min(quiet, max(0.0, deadline - time.monotonic())))
                if self._changes == before and self._tokens:
                    return

    def _add(self, key: str) -> Token | None:
        tok = self._keys.parse_token(key)
        if tok is not None:
            if key not in self._tokens:
                self._changes += 1
            self._tokens[key] = tok
            self._cond.notify_all()
        return tok

    def _on_sample(self, sample: zenoh.Sample) -> None:
        key = str(sample.key_expr)
        with self._cond:
            if sample.kind == zenoh.SampleKind.PUT:
                self._deleted.discard(key)
                tok = self._add(key)
                event = "put"
            else:
                self._deleted.add(key)
                tok = self._tokens.pop(key, None)
                self._changes += 1
                self._cond.notify_all()
                event = "delete"
            listeners = list(self._listeners)
        if tok is not None:
            for fn in listeners:
                try:
                    fn(event, tok)
                except Exception:  # noqa: BLE001, S110 (a listener must not break the graph)
                    pass

    def add_listener(self, fn: Listener) -> Callable[[], None]:
        """Call ``fn(event, token)`` on every change (``event`` is "put" or "delete").

        Returns:
            A function that removes the listener again.
        """
        with self._cond:
            self._listeners.append(fn)
        return lambda: self.remove_listener(fn)

    def remove_listener(self, fn: Listener) -> None:
        """Stop calling ``fn`` (no error if it was not registered)."""
        with self._cond:
            if fn in self._listeners:
                self._listeners.remove(fn)

    def tokens(self, kind: str | None = None) -> list[Token]:
        with self._cond:
            return [t for t in self._tokens.values() if kind is None or t.kind == kind]

    # ------------------------------------------------------------------ queries

    def nodes(self) -> list[NodeInfo]:
        return sorted(
            (NodeInfo(t.node, t.zid, t.host, t.pid, t.start_ns) for t in self.tokens("node")),
            key=lambda n: (n.name, n.start_ns),
        )

    def node_names(self) -> list[str]:
        return sorted({n.name for n in self.nodes()})

    def _by_name(self, kind: str) -> dict[str, list[str]]:
        out: dict[str, set[str]] = {}
        for t in self.tokens(kind):
            out.setdefault(t.name, set()).add(t.type)
        return {k: sorted(v) for k, v in sorted(out.items())}

    def topics(self) -> dict[str, list[str]]:
        """Topic name -> the types its publishers and subscribers declare."""
        merged: dict[str, set[str]] = {}
        for kind in ("pub", "sub"):
            for name, types in self._by_name(kind).items():
                merged.setdefault(name, set()).update(types)
        return {k: sorted(v) for k, v in sorted(merged.items())}

    def services(self) -> dict[str, list[str]]:
        return self._by_name("srv")

    def actions(self) -> dict[str, list[str]]:
        return self._by_name("act")

    def publishers(self, topic: str) -> list[Token]:
        return [t for t in self.tokens("pub") if t.name == topic]

    def subscribers(self, topic: str) -> list[Token]:
        return [t for t in self.tokens("sub") if t.name == topic]

    def servers(self, service: str) -> list[Token]:
        return [t for t in self.tokens("srv") if t.name == service]

    def action_servers(self, action: str) -> list[Token]:
        return [t for t in self.tokens("act") if t.name == action]

    def clients(self, service: str) -> list[Token]:
        """The clients of a service that nodes created (tools' one-off calls are not listed)."""
        return [t for t in self.tokens("cli") if t.name == service]

    def action_clients(self, action: str) -> list[Token]:
        return [t for t in self.tokens("actc") if t.name == action]

    def endpoints_of(self, node: str) -> dict[str, list[Token]]:
        """A node's publishers, subscribers, services and actions, servers and clients (as
        ``ros2 node info``)."""
        out: dict[str, list[Token]] = {k: [] for k in ("pub", "sub", "srv", "cli", "act", "actc")}
        for t in self.tokens():
            if t.node == node and t.kind in out:
                out[t.kind].append(t)
        return out

    def nodes_of_zid(self, zid: str, topic: str | None = None) -> list[str]:
        """Nodes of one session (optionally: those publishing ``topic``)."""
        kind = "pub" if topic else "node"
        return sorted({t.node for t in self.tokens(kind) if t.zid == zid
                       and (topic is None or t.name == topic)})

    def type_conflicts(self) -> dict[str, list[str]]:
        """Topics on which endpoints declare more than one type."""
        return {k: v for k, v in self.topics().items() if len(v) > 1}

    def duplicate_nodes(self) -> dict[str, list[NodeInfo]]:
        """Node names held by more than one live node."""
        seen: dict[str, list[NodeInfo]] = {}
        for n in self.nodes():
            seen.setdefault(n.name, []).append(n)
        return {k: v for k, v in seen.items() if len(v) > 1}

    # ------------------------------------------------------------------ waiting

    def wait_for(self, predicate: Callable[[], bool], timeout: float | None = None) -> bool:
        """Block until ``predicate()`` holds (re-checked on each graph change)."""
        deadline = None if timeout is None else time.monotonic() + timeout
        with self._cond:
            while True:
                if predicate():
                    return True
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._cond.wait(left)

    def _has(self, kind: str, name: str) -> Callable[[], bool]:
        return lambda: any(t.kind == kind and t.name == name for t in self._tokens.values())

    def wait_for_publisher(self, topic: str, timeout: float | None = None) -> bool:
        return self.wait_for(self._has("pub", topic), timeout)

    def wait_for_subscriber(self, topic: str, timeout: float | None = None) -> bool:
        return self.wait_for(self._has("sub", topic), timeout)

    def wait_for_service(self, service: str, timeout: float | None = None) -> bool:
        return self.wait_for(self._has("srv", service), timeout)

    def wait_for_action(self, action: str, timeout: float | None = None) -> bool:
        return self.wait_for(self._has("act", action), timeout)

    def wait_for_node(self, node: str, timeout: float | None = None) -> bool:
        return self.wait_for(
            lambda: any(t.kind == "node" and t.node == node for t in self._tokens.values()),
            timeout,
        )

    def close(self) -> None:
        self._sub.undeclare()  # type: ignore[no-untyped-call]
