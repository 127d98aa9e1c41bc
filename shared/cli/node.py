"""`zenros node list|info`."""

from __future__ import annotations

import argparse
from typing import Any

from ..names import resolve
from .common import CliError, add_common, open_context


def register(sub: Any) -> None:
    p = sub.add_parser("node", help="nodes: list, info")
    verbs = p.add_subparsers(dest="verb", required=True)
    v = verbs.add_parser("list", help="list nodes")
    v.add_argument("-v", "--verbose", action="store_true", help="with host, pid and session")
    v = verbs.add_parser("info", help="a node's publishers, subscribers, services, actions")
    v.add_argument("node")
    for verb in verbs.choices.values():
        add_common(verb)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args)
    try:
        g = ctx.graph
        if args.verb == "list":
            for n in g.nodes():
                print(f"{n.name}  host={n.host} pid={n.pid} session={n.zid}" if args.verbose
                      else n.name)
            dups = g.duplicate_nodes()
            for name in dups:
                print(f"WARNING: {len(dups[name])} nodes share the name {name}")
            return 0
        name = resolve(args.node, kind="node")
        if name not in g.node_names():
            raise CliError(f"unknown node {name}; known: {', '.join(g.node_names()) or 'none'}")
        eps = g.endpoints_of(name)
        print(name)
        for label, kind in (("Subscribers", "sub"), ("Publishers", "pub"),
                            ("Service Servers", "srv"), ("Service Clients", "cli"),
                            ("Action Servers", "act"), ("Action Clients", "actc")):
            print(f"  {label}:")
            for t in sorted(eps[kind], key=lambda t: t.name):
                print(f"    {t.name}: {t.type}")
        return 0
    finally:
        ctx.close()
