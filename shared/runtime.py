"""`run(NodeClass)`: flags, startup, signal capture and graceful shutdown for one node process."""

from __future__ import annotations

import argparse
import faulthandler
import os
import sys
import threading
import traceback
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager
from types import FrameType
from typing import Any, NoReturn

from .context import Context, is_session_failure
from .errors import ConfigError, StartupError
from .exits import EXIT_ERROR, EXIT_SESSION_FAILED, EXIT_STARTUP
from .log import configure_logging
from .names import Remapper
from .node import Node
from .params import parse_param_arg
from .session import add_session_arguments, options_from_args
from .shutdown import install_shutdown_listener
from .signals import handling_signals

__all__ = ["EXIT_SESSION_FAILED", "STARTUP_ERRORS", "Build", "add_node_arguments",
           "capture_signals", "main", "run", "serve"]



def add_node_arguments(parser: argparse.ArgumentParser) -> None:
    """The node flags: name, namespace, remappings, parameters, log level."""
    g = parser.add_argument_group("node")
    g.add_argument("--name", help="node name (overrides the default)")
    g.add_argument("--ns", "--namespace", dest="ns", help="node namespace")
    g.add_argument("-r", "--remap", action="append", default=[], metavar="FROM:=TO",
                   help="remap a name (also __ns:=/x, __node:=name); repeatable")
    g.add_argument("-p", "--param", action="append", default=[], metavar="NAME:=VALUE",
                   help="set a parameter (value read as YAML); repeatable")
    g.add_argument("--params-file", action="append", default=[], metavar="FILE",
                   help="ROS 2 params YAML file; repeatable")
    g.add_argument("--log-level", choices=["debug", "info", "warn", "error", "fatal"],
                   help="log level (default $ZENROS_LOG_LEVEL or info)")


def node_kwargs(ns: argparse.Namespace) -> dict[str, Any]:
    """Node constructor arguments from parsed flags."""
    overrides = {}
    for arg in ns.param:
        if ":=" not in arg and "=" in arg:
            arg = arg.replace("=", ":=", 1)
        name, value = parse_param_arg(arg)
        overrides[name] = value
    return {
        "name": ns.name,
        "namespace": ns.ns,
        "remappings": Remapper.parse(ns.remap),
        "parameter_overrides": overrides,
        "params_files": ns.params_file,
    }


def capture_signals(on_first: Callable[[], None]) -> AbstractContextManager[None]:
    """SIGINT/SIGTERM: the first calls ``on_first`` (drain), the second forces exit (130),
    after writing every thread's stack to stderr: where the drain was stuck (a launch sends
    SIGTERM when a node has not ended ``sigterm_timeout`` after its SIGINT).

    ``on_first`` runs on a thread of its own, not in the handler: the handler runs in the
    main thread between two of its bytecodes, and a main thread waiting on
    ``threading.Event.wait`` may hold the event's lock right then, so an ``Event.set`` in the
    handler would wait on it forever (seen once: a talker that ignored its SIGINT until the
    launch's SIGTERM).

    Restores the previous handlers on the way out. Only works in the main thread; elsewhere
    it does nothing.
    """
    count = 0

    def handler(signum: int, frame: FrameType | None) -> None:
        nonlocal count
        count += 1
        if count == 1:
            threading.Thread(target=on_first, name="zenros-signal", daemon=True).start()
        else:
            sys.stderr.write("forced exit; the threads were at:\n")
            faulthandler.dump_traceback(all_threads=True)
            sys.stderr.flush()
            os._exit(130)

    return handling_signals(handler)


def main(node_cls: type[Node], argv: Sequence[str] | None = None,
         prog: str | None = None) -> int:
    """Parse flags, start the node, serve until SIGINT/SIGTERM; return the exit code.

    0: clean end; 2: usage error; 3: the configuration was refused (a `ConfigError`, such
    as an invalid name, parameter value or params file, a port that cannot be bound) or there
    is no session (`StartupError`), one line on stderr; 1: anything else raised while
    starting (a bug in ``setup()``: its traceback); 4: the Zenoh session failed while
    running (`EXIT_SESSION_FAILED`).
    """
    prog = prog or node_cls.node_name or node_cls.__name__
    parser = argparse.ArgumentParser(prog=prog, description=(node_cls.__doc__ or "").strip()
                                     .split("\n")[0] or None)
    add_node_arguments(parser)
    return serve(parser, lambda ctx, args: [node_cls(context=ctx, **node_kwargs(args))], argv)


Build = Callable[[Context, argparse.Namespace], list[Node]]
"""Makes the nodes of a process on its context, from its parsed flags (the first is the one
that obeys shutdown requests); raising one of `STARTUP_ERRORS` is a startup failure (exit
code 3: the configuration was refused), any other exception a crash (exit code 1)."""

STARTUP_ERRORS = (ConfigError, StartupError)


def serve(parser: argparse.ArgumentParser, build: Build,
          argv: Sequence[str] | None = None) -> int:
    """Parse flags (the session's are added here), open the context, build the nodes, serve
    until SIGINT/SIGTERM, close the nodes in reverse order; return the exit code (`main`)."""
    prog = parser.prog
    add_session_arguments(parser)
    args = parser.parse_args(argv)
    configure_logging(args.log_level)
    stop = threading.Event()
    with capture_signals(stop.set):
        ctx: Context | None = None
        nodes: list[Node] = []
        try:
            ctx = Context(options_from_args(args), prefix=args.prefix)
            nodes = build(ctx, args)
            install_shutdown_listener(nodes[0], stop.set)
        except STARTUP_ERRORS as exc:  # what running again cannot mend
            msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            sys.stderr.write(f"{prog}: startup failed: {msg}\n")
            for made in reversed(nodes):
                made.close()
            if ctx is not None:
                ctx.close()
            return EXIT_STARTUP
        except Exception:  # noqa: BLE001 a bug: its traceback, then the crash handling
            sys.stderr.write(f"{prog}: startup failed:\n{traceback.format_exc()}")
            for made in reversed(nodes):
                made.close()
            if ctx is not None:
                ctx.close()
            return EXIT_ERROR
        node = nodes[0]
        ctx.on_failure(lambda _exc: stop.set())
        with _failing_on_panics(ctx):
            try:
                node.logger.info("started (pid %d, session %s)", os.getpid(), ctx.zid)
                # With a timeout: a signal taken by one of Zenoh's threads only flags the
                # main thread, whose handler runs when it wakes (a bare wait never would).
                while not stop.wait(0.5):
                    pass
                if ctx.failure is None:
                    node.logger.info("shutting down")
            finally:
                _close_waking(nodes if ctx.failure is None else [], ctx)
        if ctx.failure is not None:
            node.logger.critical("exiting with code %d: the Zenoh session failed (%s)",
                                 EXIT_SESSION_FAILED, type(ctx.failure).__name__)
            return EXIT_SESSION_FAILED
    return 0


def _close_waking(nodes: list[Node], ctx: Context) -> None:
    """Close ``nodes`` in reverse order, then ``ctx``, on a thread of their own while the
    main thread wakes every 0.5 s: a second SIGINT taken by one of Zenoh's threads only flags
    the main thread, whose handler (the forced exit) runs when it wakes, so a close that
    never finishes must not hold it (a broken session closes nothing: ``nodes`` empty)."""
    def close_all() -> None:
        try:
            for made in reversed(nodes):
                made.close()
        finally:
            ctx.close()

    failed: list[BaseException] = []

    def run() -> None:
        try:
            close_all()
        except BaseException as exc:  # noqa: BLE001 raised again on the main thread
            failed.append(exc)

    closer = threading.Thread(target=run, name="zenros-close", daemon=True)
    closer.start()
    while closer.is_alive():
        closer.join(0.5)
    if failed:
        raise failed[0]


@contextmanager
def _failing_on_panics(ctx: Context) -> Iterator[None]:
    """Any thread that dies of a Zenoh panic (`is_session_failure`) fails ``ctx``."""
    previous = threading.excepthook

    def hook(args: Any) -> None:
        if args.exc_value is not None and is_session_failure(args.exc_value):
            ctx.fail(args.exc_value)
        previous(args)

    threading.excepthook = hook
    try:
        yield
    finally:
        threading.excepthook = previous


def run(node_cls: type[Node], argv: Sequence[str] | None = None) -> NoReturn:
    """Run ``node_cls`` as a process (``if __name__ == "__main__": run(MyNode)``)."""
    code = main(node_cls, argv)
    if code == EXIT_SESSION_FAILED:  # Zenoh's threads outlive a broken session: do not wait
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)
