"""`Updater`: software updates of the robot (docs/robot-api.md §3.4), with pip, from the package
source the operator configured: a folder of wheels or a package index.

``check`` asks pip what an upgrade would install (``pip install --dry-run --report``) and
compares it with the installed version; ``start`` runs the upgrade in the background, its
output kept as the log; ``cancel`` stops it. Pre-releases are considered when ``use_dev`` is
on (kept in ``update.json``). An update is applied by restarting the robot's services
(``/system/restart_robot``): the running processes keep the code they started with.
Updates run only when the configuration file allows them (``allow_update``).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import signal
import sys
import threading
from importlib import metadata
from pathlib import Path
from typing import Any, Final
from urllib.parse import urlparse

import msgspec

from ..errors import Conflict, Failed, NoAnswer, Unavailable
from ..state.json_file import load_struct, save_struct

__all__ = ["Updater"]

CHECK_TIMEOUT: Final = 120.0  # s
LOG_LIMIT: Final = 64 * 1024  # bytes of the log kept


class _State(msgspec.Struct):
    use_dev: bool = False


class Updater:
    """Updates ``package`` (installed for ``python``) from ``source``; ``allowed`` says
    whether updates may run; ``folder`` keeps ``update.json`` and ``update.log``."""

    def __init__(self, source: str, package: str, allowed: bool, folder: Path,
                 python: str = sys.executable) -> None:
        self.source = source
        self.package = package
        self.allowed = allowed
        self.python = python
        self.folder = folder
        self._state = load_struct(folder / "update.json", _State)
        self._lock = threading.Lock()
        self._proc: asyncio.subprocess.Process | None = None
        self._task: asyncio.Task[None] | None = None
        self.status = "idle"  # idle, updating, complete, failed, cancelled
        self._log = bytearray()

    # ------------------------------------------------------------------ use_dev

    @property
    def use_dev(self) -> bool:
        return self._state.use_dev

    def set_use_dev(self, value: bool) -> None:
        with self._lock:
            self._state.use_dev = value
            save_struct(self.folder / "update.json", self._state)

    # ------------------------------------------------------------------ check

    def _source_args(self) -> list[str]:
        src = self.source
        if not src:
            raise Unavailable("no update source: the operator gives update_source (a folder "
                              "of wheels or a package index URL) in the gateway's "
                              "configuration file")
        if urlparse(src).scheme in ("http", "https", "file"):
            return ["--index-url", src]
        if not Path(src).is_dir():
            raise Unavailable(f"the update source {src} is not a folder of wheels or an "
                              "http(s) package index")
        return ["--no-index", "--find-links", src]

    def _pip(self, *args: str) -> list[str]:
        pre = ["--pre"] if self.use_dev else []
        return [self.python, "-m", "pip", "install", "--disable-pip-version-check",
                "--no-input", "--upgrade", *pre, *self._source_args(), *args, self.package]

    def installed(self) -> str:
        try:
            return metadata.version(self.package)
        except metadata.PackageNotFoundError:
            return ""

    async def check(self) -> dict[str, Any]:
        """``need_update`` and the versions: installed (``current``) and what an upgrade
        would install (``latest``)."""
        argv = self._pip("--dry-run", "--quiet", "--no-deps", "--report", "-")
        out, err, code = await _run(argv, CHECK_TIMEOUT)
        current = self.installed()
        if code != 0:
            last = (err.decode(errors="replace").strip().splitlines() or [""])[-1]
            raise Failed(f"pip could not check {self.source} for {self.package}: {last}")
        try:
            report = json.loads(out)
        except json.JSONDecodeError as exc:
            raise Failed(f"pip's report is not JSON: {exc}") from exc
        latest = current
        for item in report.get("install", []):
            meta = item.get("metadata", {})
            if str(meta.get("name", "")).lower().replace("_", "-") == \
                    self.package.lower().replace("_", "-"):
                latest = str(meta.get("version", ""))
        return {"status": "ok", "need_update": latest != current, "current": current,
                "latest": latest, "use_dev": self.use_dev}

    # ------------------------------------------------------------------ start, cancel, log

    async def start(self) -> None:
        """Begin the upgrade in the background.

        Raises:
            Conflict: one is under way.
            Unavailable: no source.
        """
        argv = self._pip()
        if self._task is not None and not self._task.done():
            raise Conflict("an update is under way (GET /system/update/log follows it)")
        self._log = bytearray(f"$ {' '.join(argv)}\n".encode())
        self.status = "updating"
        self._proc = await asyncio.create_subprocess_exec(
            *argv, stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.STDOUT, start_new_session=True)
        self._task = asyncio.create_task(self._follow(self._proc))

    async def _follow(self, proc: asyncio.subprocess.Process) -> None:
        assert proc.stdout is not None
        async for line in proc.stdout:
            self._log += line
            if len(self._log) > LOG_LIMIT:
                del self._log[:len(self._log) - LOG_LIMIT]
        code = await proc.wait()
        if self.status == "updating":
            self.status = "complete" if code == 0 else "failed"
            self._log += (f"pip exited with code {code}" + (
                "; restart the robot (GET /system/restart_robot) to run the new version"
                if code == 0 else "") + "\n").encode()
        self._save_log()

    def _save_log(self) -> None:
        with contextlib.suppress(OSError):
            self.folder.mkdir(parents=True, exist_ok=True)
            (self.folder / "update.log").write_bytes(bytes(self._log))

    async def cancel(self) -> None:
        """Stop the update under way (pip's own rollback keeps a half-installed package
        out); Conflict when none is."""
        proc, task = self._proc, self._task
        if proc is None or task is None or task.done():
            raise Conflict("no update is under way")
        self.status = "cancelled"
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGTERM)
        try:
            await asyncio.wait_for(asyncio.shield(task), 20)
        except TimeoutError:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
        self._log += b"cancelled\n"
        self._save_log()

    def log(self) -> dict[str, Any]:
        return {"status": self.status, "log": self._log.decode(errors="replace"),
                "is_complete": self.status in ("complete", "failed", "cancelled")}

    async def close(self) -> None:
        if self._task is not None and not self._task.done():
            await self.cancel()


async def _run(argv: list[str], timeout: float) -> tuple[bytes, bytes, int]:
    proc = await asyncio.create_subprocess_exec(
        *argv, stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE, start_new_session=True)
    try:
        out, err = await asyncio.wait_for(proc.communicate(), timeout)
    except TimeoutError:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        await proc.wait()
        raise NoAnswer(f"pip did not answer within {timeout:g} s") from None
    return out, err, proc.returncode if proc.returncode is not None else -1
