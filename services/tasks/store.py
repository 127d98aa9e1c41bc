"""`TaskStore`: task documents in SQLite, one row per task, written before a change is told.

WAL journal with ``synchronous=NORMAL``: a committed write survives the process being
killed (kill -9) at any moment; a power cut may lose the last commits (docs/tasks.md).

A row holds the `Task` Struct as msgspec JSON: nested tasks carry ``"type": "task"``. Rows
written before tasks were Structs (plain JSON documents, nested tasks untagged) are read
too, by tagging them first; such a row is rewritten in the new form at its next change.
"""

from __future__ import annotations

import sqlite3
import threading
from pathlib import Path

import msgspec
from zenros.msgs.zenros_msgs.task_docs import Task, tag_nested_tasks

__all__ = ["TaskStore"]

_SCHEMA = """
CREATE TABLE IF NOT EXISTS tasks (
    id TEXT PRIMARY KEY,
    seq INTEGER NOT NULL,
    doc BLOB NOT NULL
)
"""


class TaskStore:
    """Tasks by id, kept in creation order; every method is one committed transaction."""

    def __init__(self, path: Path | str) -> None:
        self.path = Path(path)
        if str(path) != ":memory:":
            self.path.parent.mkdir(parents=True, exist_ok=True)
        self._db = sqlite3.connect(str(path), check_same_thread=False, isolation_level=None)
        self._db.execute("PRAGMA journal_mode=WAL")
        self._db.execute("PRAGMA synchronous=NORMAL")
        self._db.execute(_SCHEMA)
        self._lock = threading.Lock()
        self._enc = msgspec.json.Encoder()
        self._dec = msgspec.json.Decoder(Task)
        row = self._db.execute("SELECT COALESCE(MAX(seq), 0) FROM tasks").fetchone()
        self._seq = int(row[0])

    def put(self, doc: Task) -> None:
        """Insert or replace ``doc`` (by its id), committed on return."""
        data = self._enc.encode(doc)
        with self._lock:
            self._seq += 1
            self._db.execute(
                "INSERT INTO tasks(id, seq, doc) VALUES(?, ?, ?) "
                "ON CONFLICT(id) DO UPDATE SET doc=excluded.doc", (doc.id, self._seq, data))

    def delete(self, task_id: str) -> None:
        with self._lock:
            self._db.execute("DELETE FROM tasks WHERE id=?", (task_id,))

    def load(self) -> list[Task]:
        """Every stored task in creation order; unreadable rows are skipped and returned
        nowhere (their ids are logged by the caller through `bad_rows`)."""
        out = []
        self.bad_rows: list[str] = []
        with self._lock:
            rows = self._db.execute("SELECT id, doc FROM tasks ORDER BY seq").fetchall()
        for task_id, data in rows:
            doc = self._decode(data)
            if doc is not None and doc.id == task_id:
                out.append(doc)
            else:
                self.bad_rows.append(task_id)
        return out

    def _decode(self, data: bytes) -> Task | None:
        """A row's task: the Struct's JSON, or a plain document of the earlier form; None
        when it is neither."""
        try:
            return self._dec.decode(data)
        except msgspec.DecodeError:
            pass
        try:
            return msgspec.convert(tag_nested_tasks(msgspec.json.decode(data)), Task)
        except (msgspec.DecodeError, msgspec.ValidationError):
            return None

    def close(self) -> None:
        with self._lock:
            self._db.close()
