"""`zenros <noun> <verb>`: the command-line entry point."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from ..errors import StartupError, ZenrosError
from ..exits import EXIT_ERROR, EXIT_STARTUP
from . import action, bag, graph, node, param, service, smach, task, tf, topic
from .common import stdout_closed



def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="zenros", description="zenros command-line tools")
    sub = parser.add_subparsers(dest="noun", required=True, metavar="COMMAND")
    for mod in (topic, service, node, graph, tf, param, action, smach, task, bag):
        mod.register(sub)
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
    parser = build_parser()
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
