"""`MediaFolder`: a folder of the robot's saved media (``Pictures``, ``Videos``;
docs/robot-api.md §3.9): file names that stay inside it, the listing, the look-up of one."""

from __future__ import annotations

import re
import time
from pathlib import Path
from typing import Any

__all__ = ["MediaError", "MediaFolder"]

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,99}$")


class MediaError(Exception):
    """A file that cannot be made or found: ``status`` is the HTTP status to answer."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status


class MediaFolder:
    """``folder``'s files ending in ``suffix`` (``.png``), called ``what`` (``saved image``)
    in errors, listed by ``GET <listed_at>``."""

    def __init__(self, folder: Path, suffix: str, what: str, listed_at: str) -> None:
        self.folder = folder
        self.suffix = suffix
        self.what = what
        self.listed_at = listed_at

    def file_name(self, filename: str) -> str:
        """``filename`` (letters, digits, ``_ - .``; its suffix added), or the time in ms."""
        if not filename:
            return f"{int(time.time() * 1000)}{self.suffix}"
        stem = filename.removesuffix(self.suffix)
        if not _NAME.match(stem):
            raise MediaError(400, f"filename {filename!r}: letters, digits, '_', '-' and "
                                  "'.' only, at most 100, not starting with a dot")
        return f"{stem}{self.suffix}"

    def listing(self) -> list[dict[str, Any]]:
        """The saved files, newest first: name, size in bytes, time (ms)."""
        if not self.folder.is_dir():
            return []
        out = []
        for p in self.folder.glob(f"*{self.suffix}"):
            st = p.stat()
            out.append({"file_timestamp": p.stem, "filename": p.name, "size": st.st_size,
                        "time": int(st.st_mtime * 1000)})
        return sorted(out, key=lambda e: e["time"], reverse=True)

    def find(self, file_timestamp: str) -> Path:
        """The file saved as ``file_timestamp`` (with or without its suffix)."""
        stem = file_timestamp.removesuffix(self.suffix)
        path = self.folder / f"{stem}{self.suffix}"
        if not _NAME.match(stem) or not path.is_file():
            raise MediaError(404, f"no {self.what} {file_timestamp!r} "
                                  f"(GET {self.listed_at} lists them)")
        return path
