"""`FileRoot`: the docs/robot-api.md §16 file system operations, confined to one sandbox folder.

Every client path is resolved inside the root: paths are relative to it (an absolute path
is accepted only when it names a place inside the root), ``..`` is refused outright, and a
path whose real location (symbolic links followed) leaves the root is refused. The root
itself cannot be deleted, renamed or moved, and ``protected`` paths (the gateway's own
config file with its password) can be neither read nor changed. No HTTP here: errors are
`FsError` subclasses that carry the HTTP status the REST layer answers with.
"""

from __future__ import annotations

import mimetypes
import os
import shutil
import stat
import tempfile
from collections.abc import Iterable, Sequence
from pathlib import Path, PurePosixPath
from typing import Any, BinaryIO

__all__ = ["BadPath", "Conflict", "FileRoot", "Forbidden", "FsError", "NotFound",
           "TooLarge"]

CHUNK = 64 * 1024


class FsError(Exception):
    """A refused file operation; ``status`` is the HTTP code that says why."""

    status = 400


class BadPath(FsError):
    """Malformed path (empty, NUL byte, ``..``) or the wrong kind of thing."""


class Forbidden(FsError):
    """The path leaves the root, is the root itself or is protected."""

    status = 403


class NotFound(FsError):
    status = 404


class Conflict(FsError):
    """The target exists already, or a folder is moved into itself."""

    status = 409


class TooLarge(FsError):
    status = 413


class FileRoot:
    """File operations on the tree under ``root`` (a missing root lists as 404)."""

    def __init__(self, root: Path, protected: Sequence[Path] = (),
                 max_upload: int = 32 * 1024 * 1024) -> None:
        self.root = Path(os.path.realpath(root))
        self.protected = [Path(os.path.realpath(p)) for p in protected]
        self.max_upload = max_upload

    # ------------------------------------------------------------------ paths

    def resolve(self, path: str) -> Path:
        """The place ``path`` names inside the root (the link itself when it is a link).

        Raises:
            BadPath: empty, a NUL byte or a ``..`` component.
            Forbidden: outside the root (absolute path or symbolic link) or protected.
        """
        if not path or not path.strip():
            raise BadPath("empty path")
        if "\x00" in path:
            raise BadPath("a NUL byte in the path")
        p = PurePosixPath(path)
        if ".." in p.parts:
            raise BadPath(f"'..' is not allowed in paths: {path!r}")
        if p.is_absolute():
            try:
                p = p.relative_to(self.root)
            except ValueError:
                raise Forbidden(f"absolute path {path!r} is outside the file root; give "
                                "paths relative to it") from None
        full = self.root.joinpath(*p.parts)
        real = Path(os.path.realpath(full))
        if not self._inside(real):
            raise Forbidden(f"{path!r} leaves the file root through a symbolic link")
        if any(q in (full, real) or self._within(real, q) for q in self.protected):
            raise Forbidden(f"{path!r} is protected")
        return full

    def relative(self, full: Path) -> str:
        rel = full.relative_to(self.root).as_posix()
        return "" if rel == "." else rel

    def _inside(self, real: Path) -> bool:
        return real == self.root or self._within(real, self.root)

    @staticmethod
    def _within(inner: Path, outer: Path) -> bool:
        return outer in inner.parents

    def _changeable(self, path: str) -> Path:
        """A path that may be deleted or moved: not the root, nothing protected inside."""
        full = self.resolve(path)
        if full == self.root:
            raise Forbidden("the file root itself cannot be deleted or moved")
        if any(self._within(q, Path(os.path.realpath(full))) for q in self.protected):
            raise Forbidden(f"{path!r} holds a protected file")
        return full

    @staticmethod
    def _exists(full: Path) -> bool:
        return full.exists() or full.is_symlink()

    def _existing(self, path: str) -> Path:
        full = self.resolve(path)
        if not self._exists(full):
            raise NotFound(f"no such file or folder: {path!r}")
        return full

    # ------------------------------------------------------------------ reads

    def file(self, path: str) -> Path:
        """An existing regular file (to download)."""
        full = self._existing(path)
        if not full.is_file():
            raise BadPath(f"{path!r} is not a file")
        return full

    def list_dir(self, path: str) -> dict[str, list[str]]:
        """``files`` and ``directories`` (names, sorted) of a folder; links as files."""
        full = self._existing(path)
        if not full.is_dir():
            raise BadPath(f"{path!r} is not a folder")
        files: list[str] = []
        dirs: list[str] = []
        with os.scandir(full) as it:
            for entry in it:
                (dirs if entry.is_dir(follow_symlinks=False) else files).append(entry.name)
        return {"files": sorted(files), "directories": sorted(dirs)}

    def info(self, path: str) -> dict[str, Any]:
        """``mode``, ``size``, ``atime``, ``mtime``, ``ctime`` (s) and ``mimetype``."""
        full = self._existing(path)
        st = full.stat()
        if stat.S_ISDIR(st.st_mode):
            mime = "inode/directory"
        else:
            mime = mimetypes.guess_type(full.name)[0] or "application/octet-stream"
        return {"mode": st.st_mode, "size": st.st_size, "atime": int(st.st_atime),
                "mtime": int(st.st_mtime), "ctime": int(st.st_ctime), "mimetype": mime}

    # ------------------------------------------------------------------ changes

    def make_dir(self, path: str) -> None:
        """Create a folder (and missing parents); 409 if something is there already."""
        full = self.resolve(path)
        if self._exists(full):
            raise Conflict(f"{path!r} exists already")
        full.mkdir(parents=True)

    def remove_file(self, path: str) -> None:
        full = self._changeable(path)
        if not self._exists(full):
            raise NotFound(f"no such file: {path!r}")
        if full.is_dir() and not full.is_symlink():
            raise BadPath(f"{path!r} is a folder; delete it with DELETE /fs/dir_api")
        full.unlink()

    def remove_dir(self, path: str) -> None:
        full = self._changeable(path)
        if not self._exists(full):
            raise NotFound(f"no such folder: {path!r}")
        if full.is_symlink() or not full.is_dir():
            raise BadPath(f"{path!r} is not a folder; delete it with DELETE /fs/file_api")
        shutil.rmtree(full)

    def remove_many(self, paths: Iterable[str]) -> None:
        """Delete files and folders; all are checked before the first is deleted."""
        targets: list[Path] = []
        for path in paths:
            full = self._changeable(path)
            if not self._exists(full):
                raise NotFound(f"no such file or folder: {path!r}")
            targets.append(full)
        for full in targets:
            if full.is_dir() and not full.is_symlink():
                shutil.rmtree(full, ignore_errors=False)
            elif self._exists(full):
                full.unlink()

    def _target(self, src: Path, to: str) -> Path:
        dst = self.resolve(to)
        if dst.is_dir() and not dst.is_symlink():
            dst = dst / src.name   # into an existing folder, under the same name
            self.resolve(self.relative(dst))
        if self._exists(dst):
            raise Conflict(f"{self.relative(dst)!r} exists already")
        if not dst.parent.is_dir():
            raise NotFound(f"no such folder: {self.relative(dst.parent)!r}")
        if src.is_dir() and not src.is_symlink() and (dst == src or self._within(dst, src)):
            raise Conflict("a folder cannot be copied or moved into itself")
        return dst

    def move(self, src_path: str, to: str) -> str:
        """Rename or move (into ``to`` when it is a folder); returns the new path."""
        src = self._changeable(src_path)
        if not self._exists(src):
            raise NotFound(f"no such file or folder: {src_path!r}")
        dst = self._target(src, to)
        shutil.move(str(src), str(dst))
        return self.relative(dst)

    def copy(self, src_path: str, to: str) -> str:
        """Copy a file or a folder (links copied as links); returns the new path."""
        src = self._existing(src_path)
        dst = self._target(src, to)
        if src.is_dir() and not src.is_symlink():
            shutil.copytree(src, dst, symlinks=True)
        else:
            shutil.copy2(src, dst, follow_symlinks=False)
        return self.relative(dst)

    def upload_target(self, path: str, filename: str) -> Path:
        """Where an upload goes: ``path`` itself, or ``path/filename`` if ``path`` is a
        folder (or ends in ``/``); the folder must exist."""
        full = self.resolve(path)
        if path.endswith("/") or (full.is_dir() and not full.is_symlink()):
            name = PurePosixPath(filename.replace("\\", "/")).name
            if not name or name in (".", ".."):
                raise BadPath("the upload has no file name; put it in `path`")
            full = self.resolve(self.relative(full / name))
        if full == self.root or (full.is_dir() and not full.is_symlink()):
            raise BadPath(f"{self.relative(full)!r} is a folder")
        if not full.parent.is_dir():
            raise NotFound(f"no such folder: {self.relative(full.parent)!r}")
        return full

    def write(self, full: Path, data: BinaryIO) -> int:
        """Copy ``data`` to ``full`` atomically, at most ``max_upload`` bytes."""
        fd, tmp = tempfile.mkstemp(dir=full.parent, prefix=".upload-")
        size = 0
        try:
            with os.fdopen(fd, "wb") as out:
                while chunk := data.read(CHUNK):
                    size += len(chunk)
                    if size > self.max_upload:
                        raise TooLarge(f"upload too large: over {self.max_upload} bytes")
                    out.write(chunk)
            os.chmod(tmp, 0o644)
            os.replace(tmp, full)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        return size
