#!/usr/bin/env python3
"""The import graph of zenros (shared/ as ``zenros``, services/ as ``zenros.services``), read
with ast: which group imports which, the import circles between modules, and the imports
from one service into another. docs/architecture.md is written from its output.

    python3 scripts/import_graph.py            # groups, circles, cross-service imports
    python3 scripts/import_graph.py --modules  # every module's imports of zenros modules
"""

from __future__ import annotations

import argparse
import ast
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TREES = {"zenros": ROOT / "shared", "zenros.services": ROOT / "services"}


def modules() -> dict[str, Path]:
    """Every module's dotted name and file."""
    out: dict[str, Path] = {}
    for package, tree in TREES.items():
        for path in sorted(tree.rglob("*.py")):
            rel = path.relative_to(tree).with_suffix("")
            parts = [p for p in rel.parts if p != "__init__"]
            if package == "zenros" and parts[:1] == ["services"]:
                continue
            out[".".join([package, *parts])] = path
    return out


def imports_of(name: str, path: Path, known: set[str], typing: bool = False) -> set[str]:
    """The zenros modules ``name`` imports at module level or in functions (and, with
    ``typing``, under ``if TYPE_CHECKING`` too)."""
    is_package = path.name == "__init__.py"
    tree = ast.parse(path.read_text(), str(path))
    found: set[str] = set()
    typing_only: set[int] = set()
    for node in ast.walk(tree):
        if not typing and isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            typing_only.update(id(n) for b in node.body for n in ast.walk(b))
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_package else name.split(".")[:-1]
                base = base[: len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            targets = [mod] + [f"{mod}.{a.name}" for a in node.names]
        for t in targets:
            while t and t not in known:
                t = t.rpartition(".")[0]
            if t and t != name:
                found.add(t)
    return found


def group(name: str) -> str:
    """``zenros.services.nav.planning.plan`` -> ``services.nav``; ``zenros.tf.buffer`` -> ``tf``;
    top-level modules of ``zenros`` are their own group."""
    parts = name.split(".")[1:]
    if not parts:
        return "zenros"
    if parts[0] == "services":
        return ".".join(parts[:2])
    return parts[0]


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    sys.setrecursionlimit(10_000)

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(out, key=lambda c: (-len(c), c))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--modules", action="store_true", help="print every module's imports")
    args = ap.parse_args()
    mods = modules()
    known = set(mods)
    def arrows(typing: bool) -> dict[str, set[str]]:
        # a package's __init__ importing its own submodules is not an arrow between modules
        return {m: {t for t in imports_of(m, p, known, typing) if not t.startswith(m + ".")}
                for m, p in mods.items()}

    graph, typed = arrows(False), arrows(True)
    if args.modules:
        for m in sorted(graph):
            print(m, "->", ", ".join(sorted(graph[m])) or "-")
        return 0
    groups: dict[str, dict[str, int]] = defaultdict(lambda: defaultdict(int))
    for m, ts in graph.items():
        for t in ts:
            if group(m) != group(t):
                groups[group(m)][group(t)] += 1
    print("## groups: who imports whom (number of module imports)")
    for g in sorted({group(m) for m in mods}):
        deps = groups.get(g, {})
        print(f"{g}: " + (", ".join(f"{d} {n}" for d, n in sorted(deps.items())) or "-"))
    print("\n## circles between groups (a group reaches itself through others)")
    ggraph = {g: set(d) for g, d in groups.items()}
    for comp in circles(ggraph):
        print(f"{len(comp)}: " + ", ".join(comp))
    print("\n## import circles between modules, at run time")
    for comp in circles(graph):
        print(f"{len(comp)}: " + ", ".join(comp))
    print("\n## ... and counting imports for type checking only (if TYPE_CHECKING)")
    for comp in circles(typed):
        if comp not in circles(graph):
            print(f"{len(comp)}: " + ", ".join(comp))
    print("\n## imports from one service into another")
    for m, ts in sorted(graph.items()):
        for t in sorted(ts):
            gm, gt = group(m), group(t)
            if gm.startswith("services.") and gt.startswith("services.") and gm != gt:
                print(f"{m} -> {t}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
