"""`zenros replay`: re-run services deterministically on a bag's inputs, and compare two
replays' outputs (see docs/replay.md)."""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path
from typing import Any

from ..bag.writer import COMPRESSIONS
from ..errors import ConfigError
from ..exits import EXIT_ERROR
from ..params import parse_param_arg

__all__ = ["parse_node_params", "register"]

EXIT_DIFFERENT = 1  # --compare: the two bags differ


def register(sub: Any) -> None:
    p = sub.add_parser(
        "replay", help="re-run services deterministically on a bag; compare two replays",
        description="Re-run the named services on a bag's inputs on a clock driven by the bag "
                    "(messages in log-time order, timers at their exact simulated times) and "
                    "record their outputs; or, with --compare, say whether two outputs are "
                    "identical.")
    p.add_argument("bag", nargs="?", metavar="BAG", help="input bag (directory or .mcap)")
    p.add_argument("--nodes", metavar="NAME[,NAME]", default="",
                   help="services to run (known: nav)")
    p.add_argument("-o", "--output", metavar="OUT.mcap", help="output file (MCAP)")
    p.add_argument("-p", "--param", action="append", default=[], metavar="NODE:NAME:=VALUE",
                   help="a parameter of one service, e.g. nav:max_linear_vel:=0.4 "
                        "(repeatable)")
    p.add_argument("--exclude", metavar="REGEX", default=None,
                   help="output topics not to record (default: /rosout, /parameter_events, "
                        "bond, transition_event, /diagnostics); '' records everything")
    p.add_argument("--tail", type=float, default=0.0, metavar="S",
                   help="run the clock S seconds past the last message (timers only)")
    p.add_argument("--clock-topic", metavar="TOPIC", nargs="?", const="/clock", default=None,
                   help="take the simulated time from the bag's clock messages (default "
                        "/clock) instead of its log times: for a bag recorded live from a "
                        "simulation")
    p.add_argument("--compression", choices=COMPRESSIONS, default="zstd")
    p.add_argument("--no-check", action="store_true",
                   help="do not report wall-clock reads inside callbacks")
    p.add_argument("--compare", nargs=2, metavar=("A.mcap", "B.mcap"),
                   help="compare two outputs: print 'identical' or the first difference "
                        "(exit 1)")
    p.set_defaults(func=run)


def parse_node_params(args: list[str]) -> dict[str, dict[str, Any]]:
    """``node:name:=value`` arguments as {node: {name: value}}."""
    out: dict[str, dict[str, Any]] = {}
    for arg in args:
        node, sep, rest = arg.partition(":")
        if not sep or not node or ":=" not in rest:
            raise ConfigError(f"invalid parameter {arg!r}: expected NODE:NAME:=VALUE, e.g. "
                              "nav:max_linear_vel:=0.4")
        name, value = parse_param_arg(rest)
        out.setdefault(node, {})[name] = value
    return out


def run(args: argparse.Namespace) -> int:
    if args.compare:
        return compare(Path(args.compare[0]), Path(args.compare[1]))
    if not args.bag or not args.output or not args.nodes:
        raise ConfigError("usage: zenros replay BAG --nodes nav[,...] -o OUT.mcap, or "
                          "zenros replay --compare A.mcap B.mcap")
    from ..replay.bagrun import DEFAULT_EXCLUDE, replay_bag

    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    out = Path(args.output)
    if out.exists() and out.is_dir():
        raise ConfigError(f"{out} is a directory; -o takes a file (OUT.mcap)")
    nodes = [n.strip() for n in args.nodes.split(",") if n.strip()]
    res = replay_bag(args.bag, nodes, out, params=parse_node_params(args.param),
                     exclude=DEFAULT_EXCLUDE if args.exclude is None else args.exclude,
                     tail=args.tail, compression=args.compression, check=not args.no_check,
                     clock_topic=args.clock_topic)
    print(f"replayed {res.sim_seconds:.3f} s of {args.bag} into {', '.join(nodes)} in "
          f"{res.wall_seconds:.3f} s ({res.rtf:.1f}x real time): {res.delivered} inputs "
          f"delivered, {res.recorded} outputs written to {out}")
    for topic, why in sorted(res.skipped_topics.items()):
        print(f"not fed: {topic}: {why}", file=sys.stderr)
    if res.wall_reads:
        print(f"{len(res.wall_reads)} wall-clock or random read(s) inside callbacks: outputs "
              "may differ between runs (see the warnings above)", file=sys.stderr)
    return 0


def compare(a: Path, b: Path) -> int:
    from ..replay.compare import compare_bags

    for p in (a, b):
        if not p.exists():
            print(f"zenros replay: no such bag: {p}", file=sys.stderr)
            return EXIT_ERROR
    diff = compare_bags(a, b)
    if diff is None:
        print("identical")
        return 0
    print(diff)
    return EXIT_DIFFERENT
