"""Process output: every byte to the node's log file, each line to the screen as ``[label] ...``.

The screen may be quiet: `is_chatter` lines (a zenros log record at DEBUG or INFO) then go to
the log file only, while warnings, errors and any other output (tracebacks, a program's
plain prints, ``startup failed`` lines) still show.
"""

from __future__ import annotations

import asyncio
import re
import time
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO, TextIO

__all__ = ["LogFile", "is_chatter", "pump"]

CHUNK = 65536
_CHATTER = re.compile(rb"\[(DEBUG|INFO)\] \[")


def is_chatter(line: bytes) -> bool:
    """A zenros log record below WARNING (``[INFO] [1764770000.123] [/listener]: ...``)."""
    return _CHATTER.match(line) is not None


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
    stream: asyncio.StreamReader, label: str, log: LogFile, screen: TextIO | None,
    quiet: bool = False, on_line: Callable[[bytes], None] | None = None,
) -> None:
    """Copy a child's stream until EOF: raw to ``log``, prefixed lines to ``screen``.

    A final line without a newline is printed too. Undecodable bytes show as U+FFFD on the
    screen; the log keeps them as they came. With ``quiet``, `is_chatter` lines stay off the
    screen. ``on_line`` sees every non-empty line (the supervisor keeps the last error).
    """
    pending = b""
    while chunk := await stream.read(CHUNK):
        log.write(chunk)
        if screen is None and on_line is None:
            continue
        *lines, pending = (pending + chunk).split(b"\n")
        _each(lines, on_line)
        if screen is not None:
            _show(screen, label, [ln for ln in lines if not (quiet and is_chatter(ln))])
    if pending:
        _each([pending], on_line)
        if screen is not None and not (quiet and is_chatter(pending)):
            _show(screen, label, [pending])


def _each(lines: list[bytes], on_line: Callable[[bytes], None] | None) -> None:
    if on_line is None:
        return
    for line in lines:
        if line.strip():
            on_line(line)


def _show(screen: TextIO, label: str, lines: list[bytes]) -> None:
    if not lines:
        return
    texts = (line.decode(errors="replace").rstrip("\r") for line in lines)
    try:
        screen.write("".join(f"[{label}] {text}\n" for text in texts))
        screen.flush()
    except (OSError, ValueError):  # the terminal or pipe went away: the log file keeps all
        pass
