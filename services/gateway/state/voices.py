"""`VoiceStore`: voice packages (docs/robot-api.md §3.7): recorded phrases the robot plays
instead of synthesising their text.

A package is a folder ``<root>/<package>/`` of recordings (``<md5sum>.wav`` or ``.mp3``)
and ``records.json``, its records (`Record`: the text, the recording's md5sum, file and
length, tags, when last played and how often). ``<root>/current.json`` names the active
package. Every recording is checked (a real WAV or MP3, at most ``max_file`` bytes) before
it is kept; a package archive (a zip of ``records.json`` and its recordings) is read member by
member within size limits, and only the files its records name are taken, by their base names,
so nothing lands outside the package's folder.
"""

from __future__ import annotations

import hashlib
import io
import os
import re
import shutil
import threading
import time
import zipfile
from pathlib import Path
from typing import Final

import msgspec

from .audio_check import AudioError, audio_duration
from .json_file import load_struct, save_struct

__all__ = ["MAX_FILE", "Record", "VoiceError", "VoiceStore", "valid_package_name"]

MAX_FILE: Final = 8 * 1024 * 1024  # bytes: one recording
MAX_ARCHIVE_TOTAL: Final = 200 * 1024 * 1024  # bytes: a package's recordings, unpacked
MAX_RECORDS: Final = 2000
_PACKAGE: Final = re.compile(r"^\w[\w .-]{0,63}$")


class VoiceError(Exception):
    """A request the store refuses: ``status`` is the HTTP status to answer."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status


class Record(msgspec.Struct, kw_only=True):
    """One recorded phrase, as ``GET /system/tts/records`` lists it."""

    text: str
    md5sum: str = ""
    file: str = ""
    duration: float = 0.0
    tags: list[str] = msgspec.field(default_factory=list)
    codenames: list[str] = msgspec.field(default_factory=lambda: ["all"])
    i18n: dict[str, str] = msgspec.field(default_factory=dict)
    mode: list[str] = msgspec.field(default_factory=lambda: ["all"])
    last_active: int = 0
    active_count: int = 0


class _Current(msgspec.Struct):
    package: str = ""


_records = msgspec.json.Decoder(list[Record])


def valid_package_name(name: str) -> str:
    """``name`` if it names a package (letters of any script, digits, ``_ - . space``; no
    leading dot or separator); else a 400."""
    if not _PACKAGE.match(name):
        raise VoiceError(400, f"package_name {name!r}: letters, digits, '_', '-', '.' and "
                              "spaces, at most 64, not starting with a dot")
    return name


class VoiceStore:
    """The voice packages under ``root``."""

    def __init__(self, root: Path, max_file: int = MAX_FILE) -> None:
        self.root = root
        self.max_file = max_file
        self._lock = threading.Lock()
        self._current = load_struct(root / "current.json", _Current)

    # ------------------------------------------------------------------ reading

    @property
    def current(self) -> str:
        """The active package ("" when none is)."""
        name = self._current.package
        return name if name and (self.root / name).is_dir() else ""

    def packages(self) -> list[str]:
        if not self.root.is_dir():
            return []
        return sorted(p.name for p in self.root.iterdir()
                      if p.is_dir() and (p / "records.json").is_file())

    def records(self, package: str = "") -> list[Record]:
        """The records of ``package`` (default: the active one; none when there is none)."""
        name = package or self.current
        if not name:
            return []
        path = self._package(name) / "records.json"
        try:
            return _records.decode(path.read_bytes())
        except msgspec.DecodeError as exc:
            raise VoiceError(500, f"{path}: {exc}") from exc

    def match(self, text: str) -> tuple[Record, Path] | None:
        """The active package's recording of ``text`` (whole text, case as given), counted as
        played; None when it has none."""
        with self._lock:
            name = self.current
            if not name:
                return None
            records = self.records(name)
            for rec in records:
                if rec.text == text:
                    rec.last_active = int(time.time() * 1000)
                    rec.active_count += 1
                    self._save(name, records)
                    return rec, self._package(name) / rec.file
        return None

    # ------------------------------------------------------------------ changing

    def select(self, package: str) -> None:
        """Make ``package`` the active one."""
        with self._lock:
            self._package(package)
            self._current.package = package
            save_struct(self.root / "current.json", self._current)

    def add_phrase(self, package: str, text: str, filename: str, data: bytes) -> Record:
        """Record ``text`` in ``package`` (made if new) as ``data`` (a WAV or MP3 called
        ``filename``); a phrase already there is replaced."""
        valid_package_name(package)
        rec = self._checked(text, filename, data)
        with self._lock:
            folder = self.root / package
            folder.mkdir(parents=True, exist_ok=True)
            records = self.records(package) if (folder / "records.json").is_file() else []
            if len(records) >= MAX_RECORDS and all(r.text != text for r in records):
                raise VoiceError(409, f"package {package!r} holds {MAX_RECORDS} phrases")
            (folder / rec.file).write_bytes(data)
            old = [r for r in records if r.text == text]
            records = [r for r in records if r.text != text] + [rec]
            self._save(package, records)
            self._forget(folder, old, records)
        return rec

    def delete_phrase(self, text: str, package: str = "") -> None:
        """Remove ``text`` from ``package`` (default: the active one)."""
        with self._lock:
            name = package or self.current
            if not name:
                raise VoiceError(409, "no voice package is active: give package_name")
            records = self.records(name)
            gone = [r for r in records if r.text == text]
            if not gone:
                raise VoiceError(404, f"package {name!r} has no phrase {text!r}")
            kept = [r for r in records if r.text != text]
            self._save(name, kept)
            self._forget(self._package(name), gone, kept)

    def delete_package(self, package: str) -> None:
        with self._lock:
            folder = self._package(package)
            shutil.rmtree(folder)
            if self._current.package == package:
                self._current.package = ""
                save_struct(self.root / "current.json", self._current)

    def upload_package(self, package: str, archive: bytes) -> int:
        """Make ``package`` from a zip of ``records.json`` and its recordings (replacing a
        package of that name); returns how many phrases it holds."""
        valid_package_name(package)
        try:
            zf = zipfile.ZipFile(io.BytesIO(archive))
        except zipfile.BadZipFile:
            raise VoiceError(400, "package_file is not a zip archive") from None
        with zf:
            members = {Path(i.filename).name: i for i in zf.infolist() if not i.is_dir()}
            index = members.get("records.json")
            if index is None or index.file_size > 1024 * 1024:
                raise VoiceError(400, "the package has no records.json (at most 1 MiB)")
            try:
                listed = msgspec.json.decode(zf.read(index), type=list[Record])
            except msgspec.MsgspecError as exc:
                raise VoiceError(400, f"records.json: {exc}") from None
            if len(listed) > MAX_RECORDS:
                raise VoiceError(400, f"records.json lists over {MAX_RECORDS} phrases")
            total = sum(members[r.file].file_size for r in listed if r.file in members)
            if total > MAX_ARCHIVE_TOTAL:
                raise VoiceError(413, f"the package's recordings unpack to over "
                                      f"{MAX_ARCHIVE_TOTAL} bytes")
            staged: list[tuple[Record, bytes]] = []
            for entry in listed:
                info = members.get(Path(entry.file).name)
                if info is None:
                    raise VoiceError(400, f"records.json names {entry.file!r} for "
                                          f"{entry.text!r}, which is not in the archive")
                if info.file_size > self.max_file:
                    raise VoiceError(413, f"{entry.file}: over {self.max_file} bytes")
                data = zf.read(info)
                rec = self._checked(entry.text, entry.file, data)
                rec.tags, rec.codenames, rec.i18n, rec.mode = (entry.tags, entry.codenames,
                                                               entry.i18n, entry.mode)
                staged.append((rec, data))
        with self._lock:
            tmp = self.root / f".{package}.part"
            shutil.rmtree(tmp, ignore_errors=True)
            tmp.mkdir(parents=True)
            for rec, data in staged:
                (tmp / rec.file).write_bytes(data)
            _write_records(tmp / "records.json", [r for r, _ in staged])
            folder = self.root / package
            if folder.exists():
                shutil.rmtree(folder)
            tmp.rename(folder)
        return len(staged)

    # ------------------------------------------------------------------ helpers

    def _package(self, name: str) -> Path:
        valid_package_name(name)
        folder = self.root / name
        if not (folder / "records.json").is_file():
            known = ", ".join(self.packages()) or "none"
            raise VoiceError(404, f"no voice package {name!r} (packages: {known})")
        return folder

    def _checked(self, text: str, filename: str, data: bytes) -> Record:
        if not 0 < len(text) <= 2000:
            raise VoiceError(400, "text: 1 to 2000 characters")
        if len(data) > self.max_file:
            raise VoiceError(413, f"{filename}: over {self.max_file} bytes")
        try:
            kind, seconds = audio_duration(data, filename)
        except AudioError as exc:
            raise VoiceError(400, f"{filename}: {exc}") from None
        md5 = hashlib.md5(data, usedforsecurity=False).hexdigest()
        return Record(text=text, md5sum=md5, file=f"{md5}.{kind}", duration=round(seconds, 3))

    def _save(self, package: str, records: list[Record]) -> None:
        _write_records(self.root / package / "records.json", records)

    @staticmethod
    def _forget(folder: Path, old: list[Record], kept: list[Record]) -> None:
        """Delete the recordings of ``old`` that no kept record uses."""
        used = {r.file for r in kept}
        for r in old:
            if r.file not in used:
                (folder / r.file).unlink(missing_ok=True)


def _write_records(path: Path, records: list[Record]) -> None:
    """``records.json``, written atomically (a temporary file renamed over it)."""
    tmp = path.with_suffix(".tmp")
    tmp.write_bytes(msgspec.json.format(msgspec.json.encode(records), indent=1))
    os.replace(tmp, path)
