"""``python -m zenros.bag record|play ...``: the bag verbs as launch nodes (they take the node
flags ``--name --ns`` that `zenros launch` adds before the verb)."""

from __future__ import annotations

import argparse
import sys

from ..cli.bag import add_play_arguments, add_record_arguments, play, record
from ..errors import ZenrosError
from ..session import add_session_arguments


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m zenros.bag")
    parser.add_argument("--name", help="node name")
    parser.add_argument("--ns", "--namespace", dest="ns", help="node namespace")
    parser.add_argument("-r", "--remap", action="append", default=[], help=argparse.SUPPRESS)
    parser.add_argument("--params-file", action="append", default=[], help=argparse.SUPPRESS)
    add_session_arguments(parser)
    verbs = parser.add_subparsers(dest="verb", required=True)
    add_record_arguments(verbs.add_parser("record", help="record topics"))
    add_play_arguments(verbs.add_parser("play", help="play a bag"))
    args = parser.parse_args(argv)
    try:
        return record(args) if args.verb == "record" else play(args)
    except (ZenrosError, ValueError) as exc:
        sys.stderr.write(f"zenros bag {args.verb}: {exc}\n")
        return 1
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main())
