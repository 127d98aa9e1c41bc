"""`ProgramStore`: the Blockly programs (docs/robot-api.md §10) in the tasks service's SQLite
file, one row per program, each checked (`blockly.parse`) before it is kept."""

from __future__ import annotations

import sqlite3
import threading
import time
import uuid
from collections.abc import Sequence
from pathlib import Path
from typing import Final

import msgspec
from zenros.msgs.zenros_msgs.blockly import BlocklyProgram

from .blockly import ProgramError, parse

__all__ = ["MAX_PROGRAMS", "ProgramStore"]

MAX_PROGRAMS: Final = 1000
FIELDS: Final = ("title", "description", "blocklyxml", "py", "is_enabled")
_SCHEMA = """
CREATE TABLE IF NOT EXISTS blockly (
    id TEXT PRIMARY KEY,
    doc BLOB NOT NULL
)
"""


class UnknownProgramError(LookupError):
    """No program has that id."""


class ProgramStore:
    """Programs by id; every change one committed transaction."""

    def __init__(self, path: Path | str) -> None:
        self._db = sqlite3.connect(str(path), check_same_thread=False, isolation_level=None)
        self._db.execute("PRAGMA journal_mode=WAL")
        self._db.execute(_SCHEMA)
        self._lock = threading.Lock()
        self._enc = msgspec.json.Encoder()
        self._dec = msgspec.json.Decoder(BlocklyProgram)

    def list(self) -> list[BlocklyProgram]:
        with self._lock:
            rows = self._db.execute("SELECT doc FROM blockly").fetchall()
        programs = [self._dec.decode(r[0]) for r in rows]
        return sorted(programs, key=lambda p: p.create_time)

    def get(self, program_id: str) -> BlocklyProgram:
        with self._lock:
            row = self._db.execute("SELECT doc FROM blockly WHERE id=?",
                                   (program_id,)).fetchone()
        if row is None:
            raise UnknownProgramError(f"no Blockly program {program_id!r}")
        return self._dec.decode(row[0])

    def save(self, program: BlocklyProgram, fields: Sequence[str]) -> BlocklyProgram:
        """Create ``program`` (no id) or change the ``fields`` of the stored one (all when
        empty); the XML is checked first (`ProgramError`)."""
        unknown = sorted(set(fields) - set(FIELDS))
        if unknown:
            raise ProgramError(f"unknown field(s) {', '.join(unknown)}; fields: "
                               + ", ".join(FIELDS))
        now = int(time.time() * 1000)
        if program.id:
            stored = self.get(program.id)
            for name in fields or FIELDS:
                setattr(stored, name, getattr(program, name))
            stored.update_time = now
            program = stored
        else:
            if len(self.list()) >= MAX_PROGRAMS:
                raise ProgramError(f"{MAX_PROGRAMS} programs are stored: delete one first")
            program = msgspec.structs.replace(program, id=str(uuid.uuid4()), create_time=now,
                                              update_time=now)
        if program.blocklyxml:
            parse(program.blocklyxml)
        with self._lock:
            self._db.execute("INSERT INTO blockly(id, doc) VALUES(?, ?) ON CONFLICT(id) DO "
                             "UPDATE SET doc=excluded.doc", (program.id, self._enc.encode(program)))
        return program

    def delete(self, program_id: str) -> None:
        self.get(program_id)
        with self._lock:
            self._db.execute("DELETE FROM blockly WHERE id=?", (program_id,))

    def close(self) -> None:
        with self._lock:
            self._db.close()
