"""The durable parameter store: the parameter tree on SQLite, with listeners and replica merge."""

from __future__ import annotations

import hashlib
import logging
import os
import sqlite3
import threading
import time
import uuid
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from types import TracebackType
from typing import Self, TypeVar

import msgspec
from zenros.errors import ParameterError, ParameterSourceError

from .param_tree import Change, Entry, ParamTree, Stamp, encode_entries, ntp64
from .param_value import MAX_NAME_LENGTH, Value, canonical, check_value
from .param_yaml import dump_yaml, parse_yaml

__all__ = ["ChangeListener", "EntryListener", "ParamStore"]

log = logging.getLogger(__name__)
T = TypeVar("T")

ChangeListener = Callable[[Change], None]
"""Called once per visible leaf that changed, after the write is committed."""
EntryListener = Callable[[Sequence[Entry]], None]
"""Called with the rows each commit stored (local writes and merged ones), for replication."""

_SCHEMA = (
    (
        "CREATE TABLE IF NOT EXISTS params (name TEXT PRIMARY KEY, time BLOB NOT NULL,"
        " source TEXT NOT NULL, deleted INTEGER NOT NULL, value BLOB) WITHOUT ROWID"
    ),
    "CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL) WITHOUT ROWID",
)
_MAX_TIME = 2**64


class ParamStore:
    """Parameters persisted in SQLite: every write is on disk before the call returns.

    The database runs in WAL mode with ``synchronous=FULL`` and an exclusive lock, so a
    second process opening the same file fails at once instead of diverging. All methods are
    thread-safe; listeners run on the writing thread, in commit order, under the store's lock,
    so they must not block (they may read the store).

    Args:
        path: the database file (created with its directory), or ``":memory:"``.
        source: this replica's id, the tie-break in stamps; by default a random id kept in
            the database.

    Raises:
        ParameterError: the database is locked by another process or unreadable.
    """

    def __init__(self, path: str | os.PathLike[str], *, source: str | None = None) -> None:
        self.path = str(path)
        if self.path != ":memory:":
            Path(self.path).parent.mkdir(parents=True, exist_ok=True)
        self._lock = threading.RLock()
        self._listeners: list[ChangeListener] = []
        self._entry_listeners: list[EntryListener] = []
        self._db = sqlite3.connect(
            self.path, isolation_level=None, check_same_thread=False, timeout=0
        )
        try:
            self.source, rows = self._open(source)
        except sqlite3.Error as exc:
            self._db.close()
            why = "in use by another process" if "locked" in str(exc) else str(exc)
            raise ParameterSourceError(f"cannot open parameter database {self.path}: {why}") from exc
        self._tree = ParamTree(rows)
        self._last = self._tree.newest().time

    def _open(self, source: str | None) -> tuple[str, list[Entry]]:
        db = self._db
        db.execute("PRAGMA locking_mode=EXCLUSIVE")
        db.execute("PRAGMA journal_mode=WAL")
        db.execute("PRAGMA synchronous=FULL")
        db.execute("BEGIN IMMEDIATE")
        try:
            for statement in _SCHEMA:
                db.execute(statement)
            row = db.execute("SELECT value FROM meta WHERE key = 'source'").fetchone()
            if source is None:
                source = row[0] if row else uuid.uuid4().hex[:16]
            if row is None or row[0] != source:
                db.execute("INSERT OR REPLACE INTO meta VALUES ('source', ?)", (source,))
            rows = [
                Entry(name, int.from_bytes(t, "big"), src, bool(deleted),
                      None if blob is None else msgspec.msgpack.decode(blob))
                for name, t, src, deleted, blob in db.execute("SELECT * FROM params")
                if _loadable(name)
            ]
            db.execute("COMMIT")
        except BaseException:
            if db.in_transaction:
                db.execute("ROLLBACK")
            raise
        return source, rows

    # ------------------------------------------------------------------ reads

    def get(self, name: str) -> Value:
        """The value at an absolute name, or the subtree under a namespace as a dict.

        Raises:
            ParameterNotFoundError: nothing is set at or under ``name``.
            InvalidNameError: ``name`` is not an absolute, valid name.
        """
        with self._lock:
            return self._tree.get(name)

    def has(self, name: str) -> bool:
        """True if a value or a non-empty namespace exists at ``name``."""
        with self._lock:
            return self._tree.has(name)

    def names(self, prefix: str = "/") -> list[str]:
        """The ``list`` operation: every leaf name at or under ``prefix``, sorted."""
        with self._lock:
            return self._tree.names(prefix)

    def search(self, namespace: str, key: str) -> str | None:
        """ROS ``searchParam`` from ``namespace`` (usually the caller's node FQN); see ParamTree."""
        with self._lock:
            return self._tree.search(namespace, key)

    def entries(self) -> list[Entry]:
        """Every row, tombstones included: what a starting replica merges."""
        with self._lock:
            return self._tree.entries()

    def changes_since(self, stamp: Stamp) -> list[Entry]:
        """Rows stamped after ``stamp``, oldest first (a full `entries` exchange is always safe)."""
        with self._lock:
            return self._tree.since(stamp)

    def digest(self) -> str:
        """A hash of every row: two replicas with equal digests hold the same parameters."""
        with self._lock:
            return hashlib.sha256(encode_entries(self._tree.entries())).hexdigest()

    def dump_yaml(self, prefix: str = "/") -> str:
        """The parameters at ``prefix`` as YAML in the ROS 2 layout (see `param_yaml.dump_yaml`).

        Raises:
            ParameterNotFoundError: nothing is set at or under ``prefix``.
        """
        with self._lock:
            return dump_yaml(self._tree.get(prefix), prefix)

    # ------------------------------------------------------------------ writes

    def set(
        self, name: str, value: Value, stamp: Stamp | None = None, *, now: int | None = None
    ) -> Stamp:
        """Set a leaf, or replace the subtree at ``name`` when ``value`` is a dict.

        Args:
            name: an absolute name (resolve others with `resolve_param_name`).
            value: bool, int, float, str, bytes, list or dict (types are kept exactly).
            stamp: the write's time; by default the store's own hybrid clock, which is later
                than every stamp the store has seen. An older stamp loses to newer rows.
            now: without ``stamp``, the physical part of that clock as an NTP64 time (the
                master passes its Zenoh session's HLC time); default the system clock.

        Returns:
            The stamp of the write, once it is committed to disk.

        Raises:
            InvalidNameError, InvalidParameterValueError: bad name, dict key or value.
        """
        with self._lock:
            stamp = self._stamp(stamp, now)
            self._commit(self._tree.plan_set(name, value, stamp))
            return stamp

    def delete(
        self, name: str, stamp: Stamp | None = None, *, now: int | None = None
    ) -> Stamp:
        """Delete the leaf or the whole subtree at ``name`` (a tombstone is kept for replicas).

        ``stamp`` and ``now`` are as in `set`.

        Raises:
            ParameterNotFoundError: nothing is set at or under ``name``.
        """
        with self._lock:
            stamp = self._stamp(stamp, now)
            self._commit(self._tree.plan_delete(name, stamp))
            return stamp

    def load_yaml(
        self, text: str, namespace: str = "/", source: str = "<string>", *,
        now: int | None = None,
    ) -> list[str]:
        """Set every parameter of a YAML document (ROS 2 or plain layout) in one commit.

        Like ``rosparam load``, this merges: each leaf is set; other names are left alone.

        Returns:
            The names set.

        Raises:
            ParameterError: the document is invalid (the message names ``source``).
        """
        leaves = parse_yaml(text, namespace, source)
        with self._lock:
            stamp = self._next_stamp(now)
            rows: list[Entry] = []
            for name, value in leaves.items():
                if value == {} and self._tree.has(name):
                    continue
                rows += self._tree.plan_set(name, value, stamp)
            self._commit(rows)
            return [r.name for r in rows]

    def merge(self, entries: Iterable[Entry]) -> list[Entry]:
        """Apply rows from a replica; per name, the newest stamp wins (ties broken by content).

        Merging is commutative and idempotent, so replicas may exchange rows in any order and
        any number of times.

        Returns:
            The rows that were newer than ours (now committed); empty if nothing changed.

        Raises:
            ParameterError, InvalidNameError: a row is malformed (nothing is applied then).
        """
        rows = [_checked(e) for e in entries]
        with self._lock:
            self._last = max([self._last, *(e.time for e in rows)])
            return self._commit(rows)

    def add_listener(self, callback: ChangeListener) -> Callable[[], None]:
        """Call ``callback`` with every change of a visible leaf; returns the remover."""
        with self._lock:
            self._listeners.append(callback)
        return lambda: self._remove(self._listeners, callback)

    def add_entry_listener(self, callback: EntryListener) -> Callable[[], None]:
        """Call ``callback`` with the rows of every commit (to forward them to replicas)."""
        with self._lock:
            self._entry_listeners.append(callback)
        return lambda: self._remove(self._entry_listeners, callback)

    def close(self) -> None:
        """Close the database (releasing its lock); further calls fail."""
        with self._lock:
            self._db.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self, t: type[BaseException] | None, e: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()

    # ------------------------------------------------------------------ internals

    def _stamp(self, given: Stamp | None, now: int | None = None) -> Stamp:
        if given is None:
            return self._next_stamp(now)
        self._last = max(self._last, given.time)
        return Stamp(*given)

    def _next_stamp(self, now: int | None = None) -> Stamp:
        """The hybrid clock: the physical time, unless a stamp already seen is later."""
        physical = ntp64(time.time_ns()) if now is None else now
        self._last = max(physical, self._last + 1)
        return Stamp(self._last, self.source)

    def _commit(self, rows: list[Entry]) -> list[Entry]:
        winners = self._tree.winners(rows)
        if not winners:
            return []
        db = self._db
        db.execute("BEGIN IMMEDIATE")
        try:
            db.executemany(
                "INSERT OR REPLACE INTO params VALUES (?, ?, ?, ?, ?)",
                [
                    (e.name, e.time.to_bytes(8, "big"), e.source, int(e.deleted),
                     None if e.deleted else msgspec.msgpack.encode(e.value))
                    for e in winners
                ],
            )
            db.execute("COMMIT")
        except BaseException:
            if db.in_transaction:
                db.execute("ROLLBACK")
            raise
        changes = self._tree.apply(winners)
        for entry_listener in list(self._entry_listeners):
            _notify(entry_listener, winners)
        for change in changes:
            for listener in list(self._listeners):
                _notify(listener, change)
        return winners

    def _remove(self, listeners: list[Callable[..., None]], callback: Callable[..., None]) -> None:
        with self._lock:
            if callback in listeners:
                listeners.remove(callback)


def _notify(callback: Callable[[T], None], arg: T) -> None:
    """Run a listener; its failure is logged and must not undo a committed write."""
    try:
        callback(arg)
    except Exception:  # a listener is a boundary: the write is already durable
        log.exception("parameter listener %r failed", callback)


def _loadable(name: str) -> bool:
    """False (with an error logged) for a stored row a current master would refuse: a name
    longer than `MAX_NAME_LENGTH` (stored before the limit existed) would otherwise go out
    on every ``get zenros/param/**`` and break Zenoh's transport (see docs/params.md)."""
    if len(name) <= MAX_NAME_LENGTH:
        return True
    log.error("skipping a stored parameter whose name is %d characters long (limit %d): "
              "%.60s...", len(name), MAX_NAME_LENGTH, name)
    return False


def _checked(e: Entry) -> Entry:
    """Validate a row from a replica: name, time range and value."""
    if not isinstance(e, Entry):
        raise ParameterError(f"cannot merge {type(e).__name__}: expected an Entry")
    if not 0 <= e.time < _MAX_TIME:
        raise ParameterError(f"cannot merge {e.name}: time {e.time} is outside NTP64")
    canonical(e.name)
    if e.deleted:
        return e if e.value is None else Entry(e.name, e.time, e.source, True)
    return Entry(e.name, e.time, e.source, False, check_value(e.value, e.name))
