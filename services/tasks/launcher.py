"""`Launcher`: ``roslaunch_action``'s launch files, each run as a ``zenros launch`` child
process of the tasks service.

Only a launch file zenros ships is run (``deploy/launch/<name>.yaml``, or the tasks service's
``launch_dir``), found by its name: ``roslaunch <pkg> <name>.launch`` names ``<name>.yaml``
(the package is not a folder here); ``name:=value`` words are its arguments. Nothing goes
through a shell and no path is taken from the request. A launch is ready once every node it
starts is in the graph; it runs until `stop` (the task's end) or `close` (the service's):
SIGINT, the launch's own Ctrl-C (it stops its processes in order), then SIGKILL to it and to
the processes it started.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Final

from zenros.errors import LaunchError
from zenros.launch.loader import load_launch
from zenros.msgs.zenros_msgs.task_actions import LAUNCH_CMD

from .outcome import Outcome

__all__ = ["Launcher", "parse_launch_cmd"]

READY_TIMEOUT: Final = 60.0  # s for a launch's nodes to come up (nav loading a map is slow)
STOP_TIMEOUT: Final = 15.0  # s for a launch to stop its processes after SIGINT
POLL: Final = 0.05
SUFFIXES: Final = (".yaml", ".yml")


def parse_launch_cmd(text: str) -> tuple[str, dict[str, str]]:
    """``launch_cmd`` as (launch file name without suffix, its arguments).

    Raises:
        ValueError: not a launch command of the accepted forms.
    """
    m = LAUNCH_CMD.match(text)
    if m is None:
        raise ValueError(f"launch_cmd {text!r} is not 'roslaunch <package> <file>.launch "
                         "[name:=value ...]'")
    args = dict(w.split(":=", 1) for w in m.group("args").split())
    return m.group("file"), args


class _Running:
    def __init__(self, proc: subprocess.Popen[bytes], log: Path) -> None:
        self.proc = proc
        self.log = log


class Launcher:
    """Launch files of ``folder`` run with ``env``, logs under ``logs``; ``node_up(fqn)`` says
    whether a node is in the graph."""

    def __init__(self, folder: Path, env: Mapping[str, str], logs: Path,
                 node_up: Callable[[str], bool]) -> None:
        self.folder = folder
        self.env = dict(env)
        self.logs = logs
        self.node_up = node_up
        self._lock = threading.Lock()
        self._running: dict[str, _Running] = {}
        self._stopping: list[threading.Thread] = []

    def files(self) -> list[str]:
        if not self.folder.is_dir():
            return []
        return sorted(p.stem for p in self.folder.iterdir()
                      if p.suffix in SUFFIXES and p.is_file())

    def find(self, name: str) -> Path:
        """Launch file ``name`` of the folder; LookupError naming the ones there are."""
        for suffix in SUFFIXES:
            path = self.folder / f"{name}{suffix}"
            if path.is_file():
                return path
        raise LookupError(f"no launch file {name!r}: the launch files are "
                          f"{', '.join(self.files()) or 'none'} (in {self.folder})")

    def start(self, launch_cmd: str, cancelled: Callable[[], bool]) -> tuple[Outcome, str]:
        """Start ``launch_cmd`` and wait until its nodes are up: the outcome, and the key to
        `stop` it by ("" when nothing runs)."""
        try:
            name, args = parse_launch_cmd(launch_cmd)
            path = self.find(name)
            nodes = [_fqn(p.namespace, p.name) for p in load_launch(path, args).processes]
        except (ValueError, LookupError, LaunchError) as exc:
            return Outcome("error", str(exc)), ""
        key = " ".join([path.name, *(f"{k}:={v}" for k, v in sorted(args.items()))])
        with self._lock:
            run = self._running.get(key)
            if run is not None and run.proc.poll() is None:
                return Outcome("complete", f"{key} runs already (pid {run.proc.pid})"), ""
            self.logs.mkdir(parents=True, exist_ok=True)
            log = self.logs / f"{path.stem}-{time.strftime('%Y%m%d-%H%M%S')}.log"
            with log.open("ab") as out:
                proc = subprocess.Popen(
                    [sys.executable, "-m", "zenros.cli", "launch", str(path),
                     *(f"{k}:={v}" for k, v in args.items()), "--control", "",
                     "--data-dir", str(self.logs)],
                    stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT,
                    env=self.env, start_new_session=True)
            run = self._running[key] = _Running(proc, log)
        end = time.monotonic() + READY_TIMEOUT
        while True:
            missing = [n for n in nodes if not self.node_up(n)]
            if not missing:
                return Outcome("complete", f"{key} started (pid {proc.pid}): "
                                           f"{', '.join(nodes) or 'no node'} up"), key
            if proc.poll() is not None:
                self.stop(key)
                return Outcome("error", f"{key} exited with code {proc.returncode} before "
                                        f"its nodes were up: {_tail(log)}"), ""
            if cancelled():
                self.stop(key)
                return Outcome("preempted"), ""
            if time.monotonic() > end:
                self.stop(key)
                return Outcome("error", f"{key}: {', '.join(missing)} not up within "
                                        f"{READY_TIMEOUT:g} s (log: {log})"), ""
            time.sleep(POLL)

    def stop(self, key: str) -> None:
        """Stop launch ``key`` and every process it started, on a thread of its own (a
        launch may take seconds to stop its processes in order; `close` waits for it)."""
        with self._lock:
            run = self._running.pop(key, None)
            if run is None:
                return
            thread = threading.Thread(target=_stop, args=(run.proc,), name=f"stop {key}")
            self._stopping = [t for t in self._stopping if t.is_alive()] + [thread]
        thread.start()

    def close(self) -> None:
        """Stop every launch and wait until they have stopped (the tasks service stops)."""
        with self._lock:
            keys = list(self._running)
        for key in keys:
            self.stop(key)
        with self._lock:
            stopping = list(self._stopping)
        for thread in stopping:
            thread.join()

    def running(self) -> dict[str, int]:
        """The launches running, and their pids."""
        with self._lock:
            return {k: r.proc.pid for k, r in self._running.items() if r.proc.poll() is None}


def _fqn(namespace: str, name: str) -> str:
    return f"{namespace.rstrip('/')}/{name}"


def _tail(log: Path, lines: int = 3) -> str:
    try:
        text = log.read_text(errors="replace").strip().splitlines()
    except OSError:
        return "(no output)"
    return " | ".join(text[-lines:]) or "(no output)"


def _stop(proc: subprocess.Popen[bytes]) -> None:
    """SIGINT (the launch stops its processes in order), then SIGKILL to what is left."""
    children = _children(proc.pid)
    if proc.poll() is None:
        _signal_group(proc.pid, signal.SIGINT)
        try:
            proc.wait(STOP_TIMEOUT)
            return
        except subprocess.TimeoutExpired:
            children = _children(proc.pid) or children
    for pid in [proc.pid, *children]:
        _signal_group(pid, signal.SIGKILL)
    try:
        proc.wait(5.0)
    except subprocess.TimeoutExpired:
        pass


def _signal_group(pid: int, sig: int) -> None:
    try:
        os.killpg(pid, sig)  # each process of a launch leads its own group
    except (ProcessLookupError, PermissionError):
        pass


def _children(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (Linux /proc; none elsewhere)."""
    out = []
    for entry in Path("/proc").iterdir() if Path("/proc").is_dir() else []:
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat.rsplit(")", 1)[-1].split()
        if len(fields) > 1 and fields[1] == str(pid):
            out.append(int(entry.name))
    return out
