"""The process supervisor behind ``zenros launch``: start, log, respawn, and stop processes.

Each process runs in its own session (process group), so a signal reaches the whole group
and a terminal's Ctrl-C reaches only the launcher, which then stops everything in order:
SIGINT to all, SIGTERM after ``sigterm_timeout`` to those still running, SIGKILL after
``sigkill_timeout``. A further `Supervisor.stop` call skips to the next step at once.
`Supervisor.restart` stops every process the same way and starts them all again, in order,
while the launch goes on (the robot API's ``restart_robot``, through `LaunchControl`).

A process that exits with code 3 (startup failed: its configuration) is not restarted; a
respawn process failing quickly again and again backs off and is given up after
``crash_limit`` runs, with one summary line. A required process that cannot be run (either
case) stops the launch.

A process *ended cleanly* if its last run exited with code 0, or, after our SIGINT, died of
SIGINT (return code -2) or exited 130. `Supervisor.run` returns 0 when every process ended
cleanly, 1 when one did not (a crash, or it needed SIGTERM or SIGKILL), and 3 when a process
could not be started at all.
"""

from __future__ import annotations

import asyncio
import inspect
import os
import shlex
import signal
import sys
import time
from collections.abc import Awaitable, Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO, TypeVar

from ..exits import EXIT_ERROR, EXIT_OK, EXIT_STARTUP
from .model import ProcessSpec, write_params_files
from .output import LogFile, pump
from .process import Event, ProcessState, describe_exit

__all__ = [
    "Event",
    "ProcessState",
    "Supervisor",
    "SupervisorConfig",
]
T = TypeVar("T")

READY_RECHECK = 1.0  # s between asks of a wait_ready hook that said "not yet"


BeforeStart = Callable[[ProcessSpec], "ProcessSpec | Awaitable[ProcessSpec]"]
WaitReady = Callable[[ProcessSpec], "bool | Awaitable[bool]"]


@dataclass
class SupervisorConfig:
    """How to supervise (the processes themselves are `ProcessSpec`s).

    Attributes:
        log_dir: this run's directory: ``<label>.log`` per process, ``launch.log``, params.
        sigterm_timeout: seconds after SIGINT before SIGTERM.
        sigkill_timeout: seconds after SIGTERM before SIGKILL.
        crash_delay: a process that ran less than this is respawned after at least this long;
            also the first wait of a crash loop's backoff (doubled at each further failure).
        crash_window: a failed run (exit code not 0) shorter than this is a *quick failure*.
        crash_limit: after this many quick failures in a row a respawn process is given up
            (one summary line); a run that lasts ``crash_window`` resets the count.
        quiet: keep `is_chatter` lines (INFO and DEBUG log records) off the screen; they
            still go to the process's log file.
        screen: where prefixed stdout lines go (default ``sys.stdout``).
        screen_err: where prefixed stderr lines and launcher messages go (``sys.stderr``).
        before_start: hook run before every (re)start; returns the spec to run (it may add
            environment or arguments, e.g. the Zenoh endpoints).
        wait_ready: hook run after every start; True when the process is ready (e.g. its
            node's liveliness token appeared). A False is reported, not fatal.
        on_event: called with every `Event` (tests wait on these).
        stop_last: processes for which it is True get their SIGINT only after the others
            have ended (or ``sigterm_timeout`` passed): the services the rest depend on, so
            an orderly stop does not make every node report them gone.
    """

    log_dir: Path
    sigterm_timeout: float = 5.0
    sigkill_timeout: float = 5.0
    crash_delay: float = 1.0
    crash_window: float = 10.0
    crash_limit: int = 5
    quiet: bool = False
    screen: TextIO | None = None
    screen_err: TextIO | None = None
    before_start: BeforeStart | None = None
    wait_ready: WaitReady | None = None
    on_event: Callable[[Event], None] | None = None
    stop_last: Callable[[ProcessSpec], bool] | None = None


class Supervisor:
    """Runs a set of processes until they end, one required process exits, or `stop`."""

    def __init__(self, specs: Sequence[ProcessSpec], config: SupervisorConfig) -> None:
        self.config = config
        self.states = {spec.label: ProcessState(spec) for spec in specs}
        self._stopping = asyncio.Event()
        self._escalate = asyncio.Event()
        self._changed = asyncio.Event()  # a restart ended: the set of watchers is new
        self._startup_failed = False
        self._restarting = False
        self._restart_task: asyncio.Task[Any] | None = None
        self._watchers: list[asyncio.Task[None]] = []
        self._watcher_of: dict[str, asyncio.Task[None]] = {}  # by label: ends once the exit is said
        self._logs: dict[str, LogFile] = {}
        self._launch_log: LogFile | None = None

    # ------------------------------------------------------------------ public

    async def run(self) -> int:
        """Start every process in order, supervise, then stop them all; return the exit code."""
        self.config.log_dir.mkdir(parents=True, exist_ok=True)
        self._launch_log = LogFile(self.config.log_dir / "launch.log")
        try:
            for state in self.states.values():
                if self._stopping.is_set() or not await self._spawn(state):
                    break
                self._watchers.append(asyncio.create_task(self._supervise(state)))
                self._watcher_of[state.spec.label] = self._watchers[-1]
            else:
                await self._until_done()
        finally:
            await self._shutdown()
            code = self.exit_code()
            self._say(Event("stop", detail=f"launch finished with exit code {code}"))
            self._launch_log.close()
        return code

    @property
    def stopping(self) -> bool:
        return self._stopping.is_set()

    @property
    def restarting(self) -> bool:
        return self._restarting

    async def restart(self, reason: str = "restart requested") -> bool:
        """Stop every process in order (as a stop does: SIGINT, then SIGTERM and SIGKILL
        for those that do not end), then start them all again in the launch's order. False
        (nothing done) while the launch stops or another restart is under way. A process
        that cannot be started again stops the launch."""
        if self._stopping.is_set() or self._restarting:
            return False
        self._restarting = True
        self._restart_task = asyncio.current_task()
        self._say(Event("restart", detail=f"{reason}: restarting every process"))
        try:
            await self._stop_processes()
            await asyncio.gather(*self._watchers, return_exceptions=True)
            self._watchers.clear()
            self._watcher_of.clear()
            for state in self.states.values():
                state.quick_failures = 0
                if self._stopping.is_set():
                    break
                if not await self._spawn(state):
                    self.stop(f"{state.spec.label} could not be started again; the launch "
                              "stops")
                    break
                self._watchers.append(asyncio.create_task(self._supervise(state)))
                self._watcher_of[state.spec.label] = self._watchers[-1]
        finally:
            self._restarting = False
            self._changed.set()
        if not self._stopping.is_set():
            self._say(Event("restart", detail=f"restarted {len(self._watchers)} processes"))
        return True

    def stop(self, reason: str = "stop requested") -> None:
        """Begin the orderly stop; each further call skips to the next signal at once."""
        if self._stopping.is_set():
            self._escalate.set()
            return
        self._say(Event("stop", detail=reason))
        self._stopping.set()

    def exit_code(self) -> int:
        """0 if every process ended cleanly, 3 if one could not start, else 1."""
        if self._startup_failed:
            return EXIT_STARTUP
        return EXIT_OK if all(s.clean for s in self.states.values()) else EXIT_ERROR

    def kill_all(self) -> None:
        """SIGKILL every live process group now (for emergencies and test teardown)."""
        for state in self.states.values():
            self._signal(state, signal.SIGKILL)

    # ------------------------------------------------------------------ running

    async def _spawn(self, state: ProcessState) -> bool:
        spec, label = state.spec, state.spec.label
        try:
            if self.config.before_start is not None:
                spec = await _maybe(self.config.before_start(spec))
            params = write_params_files(spec, self.config.log_dir / "params")
            argv = spec.argv(params)
            log = LogFile(self.config.log_dir / f"{state.spec.log_name}.log")
            log.mark(f"start: {shlex.join(argv)}")
            try:
                proc = await asyncio.create_subprocess_exec(
                    *argv,
                    stdin=asyncio.subprocess.DEVNULL,
                    stdout=asyncio.subprocess.PIPE,
                    stderr=asyncio.subprocess.PIPE,
                    env={**os.environ, "PYTHONUNBUFFERED": "1", **spec.env},
                    cwd=spec.cwd,
                    start_new_session=True,
                )
            except BaseException:
                log.close()
                raise
        except Exception as exc:  # noqa: BLE001 -- a hook or exec failure stops the launch cleanly
            state.process, state.returncode = None, None
            self._say(Event("error", label, detail=f"cannot start {label}: {exc}"))
            if state.starts == 0:
                self._startup_failed = True
                self._stopping.set()
            return False
        state.process, state.returncode, state.stop_signal, state.ready = proc, None, None, None
        state.last_error = state.last_stdout = ""
        state.starts += 1
        state.started_at = time.monotonic()
        on_screen = spec.output == "screen"
        screen = (self.config.screen or sys.stdout) if on_screen else None
        screen_err = (self.config.screen_err or sys.stderr) if on_screen else None
        assert proc.stdout is not None and proc.stderr is not None
        quiet = self.config.quiet

        def on_stdout(line: bytes) -> None:
            state.last_stdout = line.decode(errors="replace").strip()

        def on_stderr(line: bytes) -> None:
            state.last_error = line.decode(errors="replace").strip()

        state.tasks = [
            asyncio.create_task(pump(proc.stdout, label, log, screen, quiet, on_stdout)),
            asyncio.create_task(pump(proc.stderr, label, log, screen_err, quiet, on_stderr)),
        ]
        self._logs[label] = log
        self._say(Event("start", label, proc.pid, detail=shlex.join(argv)))
        if self.config.wait_ready is not None:
            state.ready_task = asyncio.create_task(self._readiness(state, spec))
        if self._stopping.is_set():  # the stop began while this (re)start was under way
            self._signal(state, signal.SIGINT)
        return True

    async def _readiness(self, state: ProcessState, spec: ProcessSpec) -> None:
        """Ask the ``wait_ready`` hook until the process is ready: a False answer is said once
        (``did not become ready; still watching for it``) and the hook is asked again,
        READY_RECHECK s apart, so a node that is only slow (a loaded host) is still reported
        ready, with how long it took. A hook that raises is said and not asked again."""
        assert self.config.wait_ready is not None
        started = time.monotonic()
        late = False
        while True:
            try:
                ok = await _maybe(self.config.wait_ready(spec))
            except Exception as exc:  # noqa: BLE001 -- a failing hook is reported as "not ready"
                state.ready = False
                self._say(Event("not_ready", state.spec.label, detail=f": {exc}"))
                return
            if ok:
                state.ready = True
                took = f" ({time.monotonic() - started:.0f} s after its start)" if late else ""
                self._say(Event("ready", state.spec.label, detail=took))
                return
            if not late:
                late = True
                state.ready = False
                self._say(Event("not_ready", state.spec.label, detail="; still watching for it"))
            await asyncio.sleep(READY_RECHECK)

    async def _supervise(self, state: ProcessState) -> None:
        spec = state.spec
        while True:
            ran = 0.0
            if state.process is not None:
                state.returncode = await state.process.wait()
                if state.ready_task is not None:
                    state.ready_task.cancel()
                await self._drain(state)
                ran = time.monotonic() - state.started_at
                log = self._logs.pop(spec.label)
                self._say(Event("exit", spec.label, state.process.pid, state.returncode,
                                describe_exit(state.returncode)), log)
                log.close()
            if self._stopping.is_set() or self._restarting:
                return
            rc = state.returncode
            if rc == EXIT_STARTUP:
                self._startup_failure(state)
                return
            if spec.required and not spec.respawn:
                self.stop(f"required process {spec.label} ended ({describe_exit(rc)})")
                return
            if not spec.respawn:
                return
            delay = self._respawn_delay(state, ran)
            if delay is None:
                if spec.required:
                    self.stop(f"required process {spec.label} keeps failing; the launch stops")
                return
            try:
                await asyncio.wait_for(self._stopping.wait(), delay)
                return
            except TimeoutError:
                pass
            await self._spawn(state)

    def _startup_failure(self, state: ProcessState) -> None:
        """Exit code 3: the process refused its configuration; running it again cannot help.

        A required process stops the launch (exit code 3); any other one stays down.
        """
        spec = state.spec
        # Its own error line is on the screen already: once is enough.
        why = "exit code 3, its error is above" if spec.output == "screen" else self._last_line(state)
        if spec.required:
            self._startup_failed = True
            self.stop(f"required process {spec.label} could not start ({why}); "
                      "the launch stops: fix its configuration")
            return
        after = "; not restarting it" if spec.respawn else ""
        self._say(Event("startup_failed", spec.label, detail=(
            f"{spec.label} could not start ({why}){after}: fix its configuration")))

    def _respawn_delay(self, state: ProcessState, ran: float) -> float | None:
        """Seconds before the next start, or None when a crash loop is given up.

        A failed run shorter than ``crash_window`` is a quick failure. The first is restarted
        as any run (after ``respawn_delay``, at least ``crash_delay`` if it ran less than
        that); from the second in a row the waits double from ``crash_delay`` (1, 2, 4 s),
        and after ``crash_limit`` in a row the process stays down with one summary line.
        """
        cfg, spec = self.config, state.spec
        quick = state.returncode != 0 and ran < cfg.crash_window
        state.quick_failures = state.quick_failures + 1 if quick else 0
        if state.quick_failures >= cfg.crash_limit:
            self._say(Event("gave_up", spec.label, detail=(
                f"{spec.label} failed {state.quick_failures} times in a row, each within "
                f"{cfg.crash_window:g} s of starting; not restarting it. Last error: "
                f"{self._last_line(state)}")))
            return None
        delay = spec.respawn_delay
        if ran < cfg.crash_delay:
            delay = max(delay, cfg.crash_delay)
        if state.quick_failures > 1:  # a single crash is restarted as before
            delay = max(delay, cfg.crash_delay * 2 ** (state.quick_failures - 2))
        return delay

    @staticmethod
    def _last_line(state: ProcessState) -> str:
        line = state.last_error or state.last_stdout
        return line or describe_exit(state.returncode)

    async def _drain(self, state: ProcessState) -> None:
        """Let the output pumps reach EOF (a leftover grandchild may hold the pipe: 1 s)."""
        if not state.tasks:
            return
        _, pending = await asyncio.wait(state.tasks, timeout=1.0)
        for task in pending:
            task.cancel()
        await asyncio.gather(*pending, return_exceptions=True)

    async def _until_done(self) -> None:
        """Until a stop is requested or every watcher has ended (a restart's new watchers
        count: the launch waits through a restart)."""
        stop = asyncio.create_task(self._stopping.wait())
        try:
            while not stop.done():
                self._changed.clear()
                watchers = {w for w in self._watchers if not w.done()}
                if not watchers and not self._restarting:
                    return
                changed = asyncio.create_task(self._changed.wait())
                try:
                    await asyncio.wait({stop, changed, *watchers},
                                       return_when=asyncio.FIRST_COMPLETED)
                finally:
                    changed.cancel()
        finally:
            stop.cancel()

    # ------------------------------------------------------------------ stopping

    async def _shutdown(self) -> None:
        self._stopping.set()
        restart = self._restart_task
        if restart is not None and restart is not asyncio.current_task():
            # it starts nothing more now, and stops what it stops in the same steps
            await asyncio.gather(restart, return_exceptions=True)
        await self._stop_processes()
        await asyncio.gather(*self._watchers, return_exceptions=True)
        for state in self.states.values():
            tasks = [*state.tasks, *([state.ready_task] if state.ready_task else [])]
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

    async def _stop_processes(self) -> None:
        """SIGINT (the `stop_last` ones after the others), SIGTERM, SIGKILL: each to those
        still running after the step before."""
        await self._stop_first_wave()
        steps = (
            (signal.SIGINT, self.config.sigterm_timeout),
            (signal.SIGTERM, self.config.sigkill_timeout),
            (signal.SIGKILL, None),
        )
        for sig, timeout in steps:
            alive = [s for s in self.states.values() if s.alive]
            if not alive:
                break
            for state in alive:
                if sig == signal.SIGINT and state.stop_signal == signal.SIGINT:
                    continue  # already asked in the first wave: a second SIGINT would
                    # interrupt its clean-up
                self._signal(state, sig)
            self._escalate.clear()
            await self._wait_watchers(timeout)

    async def _stop_first_wave(self) -> None:
        """SIGINT to every process but the `stop_last` ones, and wait for them to end."""
        last = self.config.stop_last
        alive = [s for s in self.states.values() if s.alive]
        first = [s for s in alive if last is not None and not last(s.spec)]
        if not first or len(first) == len(alive):
            return
        for state in first:
            self._signal(state, signal.SIGINT)
        self._escalate.clear()
        deadline = time.monotonic() + self.config.sigterm_timeout
        # Until each has ended and its end is said ("exited ..."): the `stop_last` ones are
        # signalled after that line, not only after the process is reaped.
        watchers = [self._watcher_of[s.spec.label] for s in first
                    if s.spec.label in self._watcher_of]
        while ((any(s.alive for s in first) or not all(w.done() for w in watchers))
               and time.monotonic() < deadline and not self._escalate.is_set()):
            await asyncio.sleep(0.02)

    async def _wait_watchers(self, timeout: float | None) -> None:
        """Until every watcher ends, ``timeout`` passes, or another `stop` escalates."""
        pending: set[asyncio.Task[Any]] = {w for w in self._watchers if not w.done()}
        if not pending:
            return
        escalate = asyncio.create_task(self._escalate.wait())
        deadline = None if timeout is None else time.monotonic() + timeout
        try:
            while pending and not escalate.done():
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    return
                _, pending = await asyncio.wait(
                    {*pending, escalate}, timeout=left, return_when=asyncio.FIRST_COMPLETED
                )
                pending.discard(escalate)
        finally:
            escalate.cancel()

    def _signal(self, state: ProcessState, sig: int) -> None:
        if not state.alive or state.process is None:
            return
        try:
            os.killpg(state.process.pid, sig)
        except ProcessLookupError:
            return
        state.stop_signal = sig
        self._say(Event("signal", state.spec.label, state.process.pid,
                        detail=signal.Signals(sig).name))

    # ------------------------------------------------------------------ reporting

    def _say(self, event: Event, log: LogFile | None = None) -> None:
        text = event.text
        if log is not None:
            log.mark(text)
        if self._launch_log is not None and not self._launch_log.closed:
            self._launch_log.mark(text)
        out = self.config.screen_err or sys.stderr
        try:
            out.write(f"[launch] {text}\n")
            out.flush()
        except (OSError, ValueError):  # stderr went away (a closed pipe): launch.log has it
            pass
        if self.config.on_event is not None:
            self.config.on_event(event)


async def _maybe(value: T | Awaitable[T]) -> T:
    """The value of a hook that may be sync or async."""
    if inspect.isawaitable(value):
        return await value
    return value
