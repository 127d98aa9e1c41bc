"""`zenros diag`: print the aggregated diagnostics tree (``/diagnostics_agg``)."""

from __future__ import annotations

import argparse
import json
import threading
import time
from typing import Any

from ..diagnostics.aggregator import toplevel_state
from ..diagnostics.tree import format_tree, tree_data
from ..msgs.diagnostic_msgs import DiagnosticArray
from .common import CliError, ToolNode, add_common, open_context


def register(sub: Any) -> None:
    p = sub.add_parser("diag", help="the robot's diagnostics tree (from the aggregator)",
                       description="Print each /diagnostics_agg tree the aggregator "
                                   "(python -m zenros.services.diagnostics) publishes.")
    p.add_argument("--once", action="store_true", help="print one tree and exit")
    p.add_argument("-v", "--values", action="store_true", help="show each status's values")
    p.add_argument("--json", action="store_true", help="one JSON object per tree")
    p.add_argument("--robot", default="", help="a robot's own tree, /ROBOT/diagnostics_agg "
                                              "(a fleet's or a station's robots: robot.yaml)")
    p.add_argument("--timeout", type=float, default=0.0,
                   help="give up after N seconds (exit code 1 if no tree came); "
                        "--once waits 10 s unless given")
    add_common(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args, settle=False, required=False,
                       waiting_for="/diagnostics_agg (is the aggregator running?)")
    trees: list[DiagnosticArray] = []
    got = threading.Condition()

    def on_tree(msg: DiagnosticArray) -> None:
        with got:
            trees.append(msg)
            got.notify_all()

    timeout = args.timeout or (10.0 if args.once else 0.0)
    deadline = time.monotonic() + timeout if timeout else None
    shown = 0
    try:
        node = ToolNode("zenros_diag", context=ctx)
        topic = f"/{args.robot.strip('/')}/diagnostics_agg" if args.robot.strip("/") \
            else "/diagnostics_agg"
        node.create_subscription(DiagnosticArray, topic, on_tree, 1)
        while True:
            with got:
                while not trees:
                    left = None if deadline is None else deadline - time.monotonic()
                    if left is not None and left <= 0:
                        if shown:
                            return 0
                        raise CliError(f"no diagnostics tree on {topic} within "
                                       f"{timeout:g} s: is the aggregator running? "
                                       "(python -m zenros.services.diagnostics)")
                    got.wait(left if left is not None else 0.5)
                tree = trees.pop()
                trees.clear()
            _show(tree, args)
            shown += 1
            if args.once:
                return 0
    finally:
        ctx.close()


def _show(tree: DiagnosticArray, args: argparse.Namespace) -> None:
    top = toplevel_state(tree.status)  # as the aggregator computes it, from this very tree
    if args.json:
        print(json.dumps({"stamp": tree.header.stamp.to_sec(),
                          "toplevel": top.message,
                          "status": tree_data(tree.status)}), flush=True)
        return
    if not args.once:
        print(f"--- {time.strftime('%H:%M:%S')}")
    print(format_tree(tree.status, top, values=args.values), flush=True)
