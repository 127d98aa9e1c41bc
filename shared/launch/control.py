"""`LaunchControl`: a running launch's services, so the robot API's ``restart_robot`` and
``shutdown`` (and ``zenros service call``) act on what the launch supervises.

``<control>/restart`` (std_srvs/Trigger) stops every process of the launch in order and starts
them again (`Supervisor.restart`); ``<control>/shutdown`` stops the launch in order, and once
everything has stopped runs the operator's ``--on-shutdown`` command (e.g. ``systemctl
poweroff`` on a real robot) if one was given on the launch's command line. Nothing received
is run: the command is the launch's own, given as an argument list.

Each answers at once and acts ``delay`` seconds later, so the answer (and a gateway's HTTP
reply, when the gateway is one of the processes it restarts) goes out first.
"""

from __future__ import annotations

import asyncio
import os
import subprocess
import threading
from collections.abc import Sequence

from ..context import Context
from ..msgs.std_srvs import Trigger, TriggerRequest, TriggerResponse
from ..names import validate_namespace
from ..node import Node
from .supervisor import Supervisor

__all__ = ["DEFAULT_CONTROL", "LaunchControl", "run_shutdown_command"]

DEFAULT_CONTROL = "/launch"
"""Where a launch's services are unless ``--control`` says otherwise."""


class LaunchControl(Node):
    """The launch's ``restart`` and ``shutdown`` services under ``control``."""

    uses_parameter_server = False  # the launch starts master: it cannot wait for it
    parameter_services = False
    parameter_events = False

    def __init__(self, ctx: Context, control: str, supervisor: Supervisor,
                 loop: asyncio.AbstractEventLoop, delay: float = 1.0) -> None:
        self.control = validate_namespace(control)
        self.supervisor = supervisor
        self.loop = loop
        self.delay = delay
        self.shutdown_requested = False
        self._lock = threading.Lock()
        self._pending = False
        super().__init__(f"launch_{os.getpid()}", context=ctx)

    def setup(self) -> None:
        self.create_service(Trigger, f"{self.control}/restart", self._restart)
        self.create_service(Trigger, f"{self.control}/shutdown", self._shutdown)

    def _busy(self) -> str:
        if self.supervisor.stopping or self.shutdown_requested:
            return "the launch is stopping"
        if self.supervisor.restarting or self._pending:
            return "a restart is under way"
        return ""

    def _restart(self, _req: TriggerRequest) -> TriggerResponse:
        with self._lock:
            busy = self._busy()
            if busy:
                return TriggerResponse(success=False, message=busy)
            self._pending = True
        n = len(self.supervisor.states)
        self.logger.info("restart requested: restarting %d processes in %g s", n, self.delay)
        self.loop.call_soon_threadsafe(self.loop.call_later, self.delay, self._start_restart)
        return TriggerResponse(success=True,
                               message=f"restarting the launch's {n} processes")

    def _start_restart(self) -> None:
        task = self.loop.create_task(self.supervisor.restart("restart requested"))
        task.add_done_callback(lambda _t: self._done_restart())

    def _done_restart(self) -> None:
        with self._lock:
            self._pending = False

    def _shutdown(self, _req: TriggerRequest) -> TriggerResponse:
        with self._lock:
            busy = self._busy()
            if busy and not self.supervisor.restarting:
                return TriggerResponse(success=False, message=busy)
            self.shutdown_requested = True
        n = len(self.supervisor.states)
        self.logger.info("shutdown requested: stopping %d processes in %g s", n, self.delay)
        self.loop.call_soon_threadsafe(self.loop.call_later, self.delay,
                                       self.supervisor.stop, "shutdown requested")
        return TriggerResponse(success=True, message=f"stopping the launch's {n} processes")


def run_shutdown_command(argv: Sequence[str]) -> int:
    """The operator's ``--on-shutdown`` command, after a requested shutdown; its exit code
    (127 when it cannot be run)."""
    print(f"[launch] running the shutdown command: {' '.join(argv)}", flush=True)
    try:
        return subprocess.run(list(argv), check=False, timeout=60).returncode
    except (OSError, subprocess.TimeoutExpired) as exc:
        print(f"[launch] the shutdown command failed: {exc}", flush=True)
        return 127
