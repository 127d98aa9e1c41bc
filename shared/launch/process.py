"""A supervised process: its state across runs, the events it produces, and clean ends."""

from __future__ import annotations

import asyncio
import signal
from dataclasses import dataclass, field

from .model import ProcessSpec

__all__ = ["Event", "ProcessState", "describe_exit"]


@dataclass(frozen=True)
class Event:
    """Something the supervisor did or saw: start, exit, ready, not_ready, signal, stop, error,
    startup_failed (exit code 3: its configuration; not restarted), gave_up (a crash loop)."""

    kind: str
    label: str = ""
    pid: int | None = None
    returncode: int | None = None
    detail: str = ""

    @property
    def text(self) -> str:
        """The launcher's line for this event."""
        if self.kind == "start":
            return f"started {self.label} (pid {self.pid}): {self.detail}"
        if self.kind == "exit":
            return f"{self.label} (pid {self.pid}) {self.detail}"
        if self.kind == "signal":
            return f"sent {self.detail} to {self.label} (pid {self.pid})"
        if self.kind == "ready":
            return f"{self.label} is ready{self.detail}"
        if self.kind == "not_ready":
            return f"{self.label} did not become ready{self.detail}"
        return self.detail



@dataclass
class ProcessState:
    """One supervised process across its runs."""

    spec: ProcessSpec
    process: asyncio.subprocess.Process | None = None
    starts: int = 0
    returncode: int | None = None
    stop_signal: int | None = None
    ready: bool | None = None
    started_at: float = 0.0
    quick_failures: int = 0
    """Failed runs in a row that each ended within ``crash_window`` of their start."""
    last_error: str = ""
    """The last line the current (or last) run wrote on stderr, else on stdout."""
    last_stdout: str = ""
    tasks: list[asyncio.Task[None]] = field(default_factory=list)
    ready_task: asyncio.Task[None] | None = None

    @property
    def alive(self) -> bool:
        return self.process is not None and self.process.returncode is None

    @property
    def clean(self) -> bool:
        """Whether the last run ended cleanly (exit 0, or SIGINT-death or 130 after our SIGINT).

        A process never started counts as clean (the launch stopped before its turn).
        """
        if self.starts == 0:
            return True
        rc = self.returncode
        if rc == 0:
            return True
        return self.stop_signal == signal.SIGINT and rc in (-signal.SIGINT, 130)


def describe_exit(rc: int | None) -> str:
    """How a run ended, in words: ``exited with code 1``, ``was killed by SIGTERM``."""
    if rc is None:
        return "did not start"
    if rc < 0:
        return f"was killed by {signal.Signals(-rc).name}"
    return f"exited with code {rc}"
