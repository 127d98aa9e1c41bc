"""`zenros <noun> <verb>`: the command-line entry point."""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from ..errors import StartupError, ZenrosError
from ..exits import EXIT_ERROR, EXIT_STARTUP
from .common import stdout_closed

# The nouns, each a module of this package with register(subparsers).
NOUNS = ("topic", "service", "node", "graph", "tf", "param", "action", "smach", "task", "bag",
         "lifecycle", "map", "diag", "interface", "doctor", "replay")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """Every noun's parser; with ``only``, that noun's alone: a command imports the module of
    its noun and no other (the other nouns' imports were a third of a short command's CPU)."""
    parser = argparse.ArgumentParser(prog="zenros", description="zenros command-line tools")
    sub = parser.add_subparsers(dest="noun", required=True, metavar="COMMAND")
    for name in NOUNS if only is None else (only,):
        importlib.import_module(f"{__package__}.{name}").register(sub)
    r = sub.add_parser("router", help="run a Zenoh router (default tcp/127.0.0.1:7447)",
                       add_help=False)
    r.set_defaults(func=None, passthrough="router")
    r = sub.add_parser("launch", help="start and supervise the processes of a launch file",
                       add_help=False)
    r.set_defaults(func=None, passthrough="launch")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["router"]:
        from ..router import main as router_main

        return router_main(argv[1:])
    if argv[:1] == ["launch"]:
        from ..launch.cli import main as launch_main
        from ..launch.zenoh_hooks import ZenohLaunch

        return launch_main(argv[1:], ZenohLaunch().hooks())
    parser = build_parser(argv[0] if argv and argv[0] in NOUNS else None)
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except StartupError as exc:
        sys.stderr.write(f"zenros: {str(exc).splitlines()[0]}\n")
        return EXIT_STARTUP
    except (ZenrosError, ValueError) as exc:
        sys.stderr.write(f"zenros {args.noun}: {exc}\n")
        return EXIT_ERROR
    except KeyboardInterrupt:
        return 0
    except BrokenPipeError:  # `zenros topic echo /chatter | head -4`: the reader has enough
        stdout_closed()
        return 0


if __name__ == "__main__":
    sys.exit(main())
