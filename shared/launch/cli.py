"""``zenros launch <file> [name:=value ...]``: load a launch file and supervise its processes."""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import os
import shlex
import signal
import sys
import time
from collections.abc import AsyncIterator, Callable, Sequence
from contextlib import AbstractAsyncContextManager
from dataclasses import dataclass
from pathlib import Path

from ..errors import LaunchError, StartupError
from ..exits import EXIT_STARTUP
from ..names import validate_namespace
from .args import describe as describe_arg
from .files import describe, find_launch_file, launch_dir, launch_files
from .loader import declared_args, load_launch
from .model import LaunchDescription, ProcessSpec
from .supervisor import BeforeStart, Event, Supervisor, SupervisorConfig, WaitReady

__all__ = ["LaunchHooks", "LaunchOptions", "add_arguments", "default_data_dir", "main", "run"]


@dataclass(frozen=True)
class LaunchOptions:
    """The parsed command line of ``zenros launch``."""

    file: Path
    args: dict[str, str]
    data_dir: Path
    run_dir: Path
    no_router: bool = False
    sigterm_timeout: float = 5.0
    sigkill_timeout: float = 5.0
    verbose: bool = False
    control: str = "/launch"
    on_shutdown: tuple[str, ...] = ()


@dataclass(frozen=True)
class LaunchHooks:
    """What the Zenoh side plugs into a launch; every hook is optional.

    Attributes:
        startup: entered before the first process starts and exited after the last one
            stopped, e.g. to start a local router unless ``options.no_router`` or one is
            reachable. Raising `StartupError` ends the launch with exit code 3.
        before_start: called before every (re)start with the process spec; returns the spec
            to run (e.g. with the router endpoint added to its environment).
        wait_ready: called after every start; True once the node is up (its liveliness).
        on_event: sees every supervisor `Event`.
        stop_last: True for processes stopped after all the others (e.g. master).
        control: entered once the processes' supervisor exists, exited after it ended: the
            launch's own services (restart, shutdown) under ``options.control``.
    """

    startup: Callable[[LaunchOptions], AbstractAsyncContextManager[object]] | None = None
    before_start: BeforeStart | None = None
    wait_ready: WaitReady | None = None
    on_event: Callable[[Event], None] | None = None
    stop_last: Callable[[ProcessSpec], bool] | None = None
    control: Callable[[Supervisor, LaunchOptions],
                      AbstractAsyncContextManager[object]] | None = None


def default_data_dir() -> Path:
    """``$ZENROS_HOME``, else ``~/.zenros``."""
    return Path(os.environ.get("ZENROS_HOME") or Path.home() / ".zenros").expanduser()


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The flags of ``zenros launch`` (shared with the ``zenros`` dispatcher)."""
    parser.add_argument(
        "file", type=Path, nargs="?",
        help="the launch file (YAML): a path, or the name of one zenros carries (see --list)",
    )
    parser.add_argument(
        "launch_args", nargs="*", metavar="name:=value", help="values for the file's args"
    )
    parser.add_argument("--no-router", action="store_true", help="do not start a Zenoh router")
    parser.add_argument(
        "--data-dir", type=Path, default=None,
        help="where logs go (default: $ZENROS_HOME or ~/.zenros)",
    )
    parser.add_argument(
        "--sigterm-timeout", type=float, default=5.0, metavar="S",
        help="seconds between SIGINT and SIGTERM at shutdown (default 5)",
    )
    parser.add_argument(
        "--sigkill-timeout", type=float, default=5.0, metavar="S",
        help="seconds between SIGTERM and SIGKILL at shutdown (default 5)",
    )
    parser.add_argument(
        "--control", default="/launch", metavar="NAME",
        help="where the launch's restart and shutdown services are (std_srvs/Trigger: "
             "NAME/restart, NAME/shutdown; the robot API's restart_robot and shutdown call "
             "them; default /launch; '' for none)",
    )
    parser.add_argument(
        "--on-shutdown", default="", metavar="CMD",
        help="a command run after a shutdown requested on NAME/shutdown has stopped every "
             "process, e.g. 'systemctl poweroff' on a real robot (split like a shell would, "
             "never run by one)",
    )
    parser.add_argument(
        "-v", "--verbose", action="store_true",
        help="print the processes' INFO and DEBUG log lines too (default: only in their logs)",
    )
    parser.add_argument(
        "--list", dest="list_files", action="store_true",
        help="list the launch files zenros carries and exit",
    )
    parser.add_argument(
        "--show-args", action="store_true", help="list the file's arguments and exit"
    )
    parser.add_argument(
        "--print", dest="print_only", action="store_true",
        help="print each process's command line and exit",
    )


def _parse_args(values: Sequence[str], parser: argparse.ArgumentParser) -> dict[str, str]:
    out: dict[str, str] = {}
    for item in values:
        name, sep, value = item.partition(":=")
        if not sep or not name:
            parser.error(f"launch arguments are written name:=value, got {item!r}")
        out[name] = value
    return out


def main(argv: Sequence[str] | None = None, hooks: LaunchHooks | None = None) -> int:
    """Run ``zenros launch``; returns the exit code (0 clean, 1 a process failed, 2 usage, 3
    the launch could not start)."""
    parser = argparse.ArgumentParser(
        prog="zenros launch", description="Start and supervise the processes of a launch file."
    )
    add_arguments(parser)
    try:
        ns = parser.parse_intermixed_args(argv)
        launch_args = _parse_args(ns.launch_args, parser)
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else 2
    if ns.list_files:
        return _list_files()
    if ns.file is None:
        parser.print_usage(sys.stderr)
        print("zenros launch: give a launch file (a path, or a name from --list)", file=sys.stderr)
        return 2
    try:
        ns.file = find_launch_file(ns.file)
    except LaunchError as exc:
        print(f"zenros launch: {exc}", file=sys.stderr)
        return EXIT_STARTUP
    if ns.show_args:
        return _show_args(ns.file)
    if ns.control:
        try:
            validate_namespace(ns.control)
        except ValueError as exc:
            print(f"zenros launch: --control {ns.control!r}: {exc}", file=sys.stderr)
            return 2
    try:
        on_shutdown = tuple(shlex.split(ns.on_shutdown))
    except ValueError as exc:
        print(f"zenros launch: --on-shutdown {ns.on_shutdown!r}: {exc}", file=sys.stderr)
        return 2
    data_dir = (ns.data_dir or default_data_dir()).expanduser()
    run_id = time.strftime("%Y%m%d-%H%M%S") + f"-{os.getpid()}"
    options = LaunchOptions(
        file=ns.file, args=launch_args, data_dir=data_dir,
        run_dir=data_dir / "logs" / run_id, no_router=ns.no_router,
        sigterm_timeout=ns.sigterm_timeout, sigkill_timeout=ns.sigkill_timeout,
        verbose=ns.verbose, control=ns.control, on_shutdown=on_shutdown,
    )
    try:
        description = load_launch(options.file, options.args)
    except LaunchError as exc:
        print(f"zenros launch: {exc}", file=sys.stderr)
        return EXIT_STARTUP
    if ns.print_only:
        for spec in description.processes:
            params = [p if isinstance(p, str) else "<inline params>" for p in spec.params]
            print(f"{spec.label}: {shlex.join(spec.argv(params))}")
        return 0
    return asyncio.run(run(description, options, hooks or LaunchHooks()))


async def run(description: LaunchDescription, options: LaunchOptions, hooks: LaunchHooks) -> int:
    """Supervise a loaded launch until it ends; Ctrl-C (SIGINT) or SIGTERM stop it in order."""
    options.run_dir.mkdir(parents=True, exist_ok=True)
    _link_latest(options.run_dir)
    supervisor = Supervisor(
        description.processes,
        SupervisorConfig(
            log_dir=options.run_dir,
            sigterm_timeout=options.sigterm_timeout,
            sigkill_timeout=options.sigkill_timeout,
            quiet=not options.verbose,
            before_start=hooks.before_start,
            wait_ready=hooks.wait_ready,
            on_event=hooks.on_event,
            stop_last=hooks.stop_last,
        ),
    )
    startup = hooks.startup(options) if hooks.startup else _nothing()
    try:
        async with startup, _signals(supervisor), _control(hooks, supervisor, options):
            return await supervisor.run()
    except StartupError as exc:
        print(f"zenros launch: {exc}", file=sys.stderr)
        return EXIT_STARTUP


@contextlib.asynccontextmanager
async def _nothing() -> AsyncIterator[None]:
    yield


def _control(hooks: LaunchHooks, supervisor: Supervisor,
             options: LaunchOptions) -> AbstractAsyncContextManager[object]:
    if hooks.control is None or not options.control:
        return _nothing()
    return hooks.control(supervisor, options)


@contextlib.asynccontextmanager
async def _signals(supervisor: Supervisor) -> AsyncIterator[None]:
    """SIGINT and SIGTERM call `Supervisor.stop` while the launch runs (main thread only)."""
    loop = asyncio.get_running_loop()
    installed = []
    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            loop.add_signal_handler(sig, supervisor.stop, f"received {signal.Signals(sig).name}")
        except (RuntimeError, ValueError):  # not the main thread: the caller handles signals
            continue
        installed.append(sig)
    try:
        yield
    finally:
        for sig in installed:
            loop.remove_signal_handler(sig)


def _link_latest(run_dir: Path) -> None:
    """Point ``logs/latest`` at this run (best effort)."""
    latest = run_dir.parent / "latest"
    tmp = run_dir.parent / f".latest-{os.getpid()}"
    try:
        tmp.unlink(missing_ok=True)
        tmp.symlink_to(run_dir.name)
        tmp.replace(latest)
    except OSError:
        return


def _list_files() -> int:
    """``--list``: each launch file zenros carries, with the first sentence of its header."""
    files = launch_files()
    if not files:
        print(f"zenros launch: no launch files in {launch_dir()}", file=sys.stderr)
        return EXIT_STARTUP
    print(f"launch files in {launch_dir()} (run one with `zenros launch NAME`):")
    width = max(len(f.name) for f in files)
    for f in files:
        print(f"  {f.name:<{width}}  {describe(f)}".rstrip())
    return 0


def _show_args(file: Path) -> int:
    try:
        decls = declared_args(file)
    except LaunchError as exc:
        print(f"zenros launch: {exc}", file=sys.stderr)
        return EXIT_STARTUP
    if not decls:
        print(f"{file} declares no arguments")
    for d in decls:
        default = "(required)" if d.default is None else f"(default: {d.default!r})"
        kind = describe_arg(d)
        kind = f" [{kind}]" if kind else ""
        print(f"{d.name} {default}{kind}" + (f": {d.description}" if d.description else ""))
    return 0
