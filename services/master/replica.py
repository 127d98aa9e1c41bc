"""Replication between master replicas: push each local write, and pull by digest (anti-entropy).

Every replica publishes the rows of its own writes on `REPLICATION_TOPIC`; the others merge
them. Pushes can be lost (a partition, a replica not yet matched), so replicas also *pull*:
a `SYNC` query to every other replica carries the asker's digest; a replica whose digest
differs answers with all its rows, and the asker merges them and pushes back the rows the
answer lacked. A pull runs at startup (before serving), whenever another replica's `SYNC`
service appears in the graph (a start, the end of a partition, a liveliness flap), and every
``period`` seconds. Merging is idempotent and commutative (see `param_tree`), so repeated or
crossing exchanges are harmless and replicas converge on "the newest stamp wins".
"""

from __future__ import annotations

import threading
from collections.abc import Sequence

import zenoh
from zenros.codec import codec_for
from zenros.errors import CodecError, ParameterError
from zenros.names import Token
from zenros.node import Node

from .messages import REPLICATION_TOPIC, SYNC, ParamRows, Sync, SyncRequest, SyncResponse
from .param_store import ParamStore
from .param_tree import Entry

__all__ = ["Replicator"]

_REQ = codec_for(SyncRequest)
_RES = codec_for(SyncResponse)


class Replicator:
    """Keeps one store in step with the other master replicas on the same key prefix.

    Args:
        node: the master node (its session, logger, graph).
        store: the replica's store.
        period: seconds between background pulls (0 disables them).
        timeout: how long a pull waits for answers.
    """

    def __init__(self, node: Node, store: ParamStore, *, period: float = 5.0,
                 timeout: float = 2.0) -> None:
        self._node = node
        self._store = store
        self._timeout = timeout
        self._ctx = node.context
        self._key = self._ctx.keys.service(SYNC)
        self._lock = threading.Lock()
        self.closed = False
        self._pub = node.create_publisher(ParamRows, REPLICATION_TOPIC, 100)
        node.create_subscription(ParamRows, REPLICATION_TOPIC, self.on_rows, 100)
        self._remove_listener = store.add_entry_listener(self._on_commit)
        self.pull()
        node.create_service(Sync, SYNC, self.handle_sync)
        node.graph.add_listener(self._on_graph)
        if period > 0:
            node.create_timer(period, self.pull_async)

    # ------------------------------------------------------------------ push

    def _on_commit(self, rows: Sequence[Entry]) -> None:
        mine = [e for e in rows if e.source == self._store.source]
        if mine and not self.closed:
            self._pub.publish(ParamRows(source=self._store.source, entries=mine))

    def on_rows(self, msg: ParamRows) -> None:
        """Merge rows pushed by another replica."""
        if msg.source == self._store.source or self.closed:
            return
        self._merge(msg.entries, msg.source)

    def _merge(self, entries: Sequence[Entry], source: str) -> int:
        try:
            return len(self._store.merge(entries))
        except (ParameterError, ValueError) as exc:
            self._node.logger.error("rejected rows from replica %s: %s", source, exc)
            return 0

    # ------------------------------------------------------------------ pull

    def handle_sync(self, req: SyncRequest) -> SyncResponse:
        """Answer a pull: our digest, and all our rows when the asker's digest differs."""
        digest = self._store.digest()
        if req.source == self._store.source or req.digest == digest:
            return SyncResponse(source=self._store.source, digest=digest)
        return SyncResponse(source=self._store.source, digest=digest,
                            entries=self._store.entries())

    def _request(self) -> bytes:
        return _REQ.encode(SyncRequest(source=self._store.source, digest=self._store.digest()))

    def _get_args(self) -> dict[str, object]:
        return {
            "payload": self._request(),
            "encoding": _REQ.encoding,
            "target": zenoh.QueryTarget.ALL,
            "consolidation": zenoh.ConsolidationMode.NONE,
            "allowed_destination": zenoh.Locality.REMOTE,
            "timeout": self._timeout,
        }

    def pull(self) -> int:
        """Pull from every reachable replica now (blocking); returns how many answered."""
        answered = 0
        for reply in self._ctx.session.get(self._key, **self._get_args()):  # type: ignore[call-overload]
            answered += self._on_reply(reply)
        return answered

    def pull_async(self) -> None:
        """Start a pull; answers are merged as they arrive (on Zenoh's threads)."""
        if self.closed:
            return
        try:
            self._ctx.session.get(self._key, self._on_reply, **self._get_args())  # type: ignore[call-overload]
        except zenoh.ZError as exc:  # the session is closing
            self._node.logger.debug("replica pull not sent: %s", exc)

    def _on_reply(self, reply: zenoh.Reply) -> int:
        ok = reply.ok
        if ok is None or self.closed:
            return 0
        try:
            res = _RES.decode(ok.payload.to_bytes())
        except CodecError as exc:
            self._node.logger.warning("bad answer to a replica pull: %s", exc)
            return 0
        if res.source == self._store.source:
            return 0
        with self._lock:  # one reconciliation at a time keeps the log readable
            merged = self._merge(res.entries, res.source) if res.entries else 0
            if merged:
                self._node.logger.info("merged %d rows from replica %s", merged, res.source)
            if res.entries and self._store.digest() != res.digest:
                theirs = {e.name: e for e in res.entries}
                missing = [e for e in self._store.entries() if theirs.get(e.name) != e]
                if missing:
                    self._pub.publish(ParamRows(source=self._store.source, entries=missing))
        return 1

    def _on_graph(self, event: str, tok: Token) -> None:
        if (event == "put" and tok.kind == "srv" and tok.name == SYNC
                and tok.zid != self._ctx.zid):
            self.pull_async()

    def close(self) -> None:
        """Stop replicating (the node closes the endpoints)."""
        self.closed = True
        self._remove_listener()
