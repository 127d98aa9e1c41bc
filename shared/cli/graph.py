"""`zenros graph`: the computation graph as Graphviz DOT (and SVG when `dot` is installed)."""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
from typing import Any

from ..graph import Graph
from .common import CliError, add_common, open_context

HIDDEN_TOPICS = ("/rosout", "/clock", "/parameter_events")


def register(sub: Any) -> None:
    p = sub.add_parser("graph", help="the computation graph as DOT or SVG (like rqt_graph)")
    p.add_argument("-o", "--output", help="write to FILE; .svg needs Graphviz 'dot'")
    p.add_argument("--all", action="store_true", help="include /rosout, /clock and services")
    add_common(p)
    p.set_defaults(func=run)


def _q(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def to_dot(graph: Graph, include_all: bool = False) -> str:
    """Nodes as ellipses, topics as boxes, publisher → topic → subscriber edges."""
    lines = ["digraph zenros {", "  rankdir=LR;", "  node [fontname=Helvetica];"]
    for name in graph.node_names():
        lines.append(f"  {_q('n:' + name)} [label={_q(name)}, shape=ellipse];")
    edges: set[str] = set()
    for topic, types in graph.topics().items():
        if topic in HIDDEN_TOPICS and not include_all:
            continue
        tid = _q("t:" + topic)
        lines.append(f"  {tid} [label={_q(topic + chr(10) + ', '.join(types))}, shape=box];")
        for t in graph.publishers(topic):
            edges.add(f"  {_q('n:' + t.node)} -> {tid};")
        for t in graph.subscribers(topic):
            edges.add(f"  {tid} -> {_q('n:' + t.node)};")
    if include_all:
        for name, types in graph.services().items():
            sid = _q("s:" + name)
            lines.append(f"  {sid} [label={_q(name + chr(10) + ', '.join(types))}, "
                         "shape=diamond];")
            for t in graph.servers(name):
                edges.add(f"  {_q('n:' + t.node)} -> {sid} [style=dashed];")
    lines += sorted(edges)
    lines.append("}")
    return "\n".join(lines) + "\n"


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args)
    try:
        dot = to_dot(ctx.graph, args.all)
    finally:
        ctx.close()
    if not args.output:
        sys.stdout.write(dot)
        return 0
    if args.output.endswith(".svg"):
        exe = shutil.which("dot")
        if exe is None:
            raise CliError("Graphviz 'dot' is not installed (apt-get install graphviz); "
                           "write DOT with -o FILE.dot instead")
        svg = subprocess.run([exe, "-Tsvg"], input=dot.encode(), capture_output=True, check=True)
        with open(args.output, "wb") as f:
            f.write(svg.stdout)
    else:
        with open(args.output, "w", encoding="utf-8") as f:
            f.write(dot)
    print(f"wrote {args.output}")
    return 0
