"""Process output: every byte to the node's log file, each line to the screen as ``[label] ...``."""

from __future__ import annotations

import asyncio
import time
from pathlib import Path
from typing import BinaryIO, TextIO

__all__ = ["LogFile", "pump"]

CHUNK = 65536


class LogFile:
    """A per-node log file under the run directory, appended to across respawns."""

    def __init__(self, path: Path) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        self.path = path
        self._file: BinaryIO = path.open("ab")

    def write(self, data: bytes) -> None:
        self._file.write(data)
        self._file.flush()

    def mark(self, text: str) -> None:
        """A launcher line in the log (start, exit), with a wall-clock time."""
        stamp = time.strftime("%Y-%m-%d %H:%M:%S")
        self.write(f"--- [zenros launch {stamp}] {text}\n".encode())

    @property
    def closed(self) -> bool:
        return self._file.closed

    def close(self) -> None:
        self._file.close()


async def pump(
    stream: asyncio.StreamReader, label: str, log: LogFile, screen: TextIO | None
) -> None:
    """Copy a child's stream until EOF: raw to ``log``, prefixed lines to ``screen``.

    A final line without a newline is printed too. Undecodable bytes show as U+FFFD on the
    screen; the log keeps them as they came.
    """
    pending = b""
    while chunk := await stream.read(CHUNK):
        log.write(chunk)
        if screen is None:
            continue
        *lines, pending = (pending + chunk).split(b"\n")
        _show(screen, label, lines)
    if screen is not None and pending:
        _show(screen, label, [pending])


def _show(screen: TextIO, label: str, lines: list[bytes]) -> None:
    if not lines:
        return
    texts = (line.decode(errors="replace").rstrip("\r") for line in lines)
    try:
        screen.write("".join(f"[{label}] {text}\n" for text in texts))
        screen.flush()
    except (OSError, ValueError):  # the terminal or pipe went away: the log file keeps all
        pass
