#!/usr/bin/env python3
"""The import graph of zenros (shared/ as ``zenros``, services/ as ``zenros.services``), read
with ast: which group imports which, the import circles between modules, the imports from
one service into another, and the gateway's imports that point the wrong way between its
layers. docs/architecture.md is written from its output.

    python3 scripts/import_graph.py            # groups, circles, wrong-way imports
    python3 scripts/import_graph.py --modules  # every module's imports of zenros modules
    python3 scripts/import_graph.py --check    # exit 1 if an import points the wrong way,
                                               # or the library (shared/) has an import circle
"""

from __future__ import annotations

import argparse
import ast
import sys
from collections import defaultdict
from collections.abc import Iterator
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TREES = {"zenros": ROOT / "shared", "zenros.services": ROOT / "services"}
GATEWAY = "zenros.services.gateway"
# The gateway's layers, lowest first: a module imports only its own layer or lower ones.
# Doors (protocol front ends) sit on the ports to the robot; ports never import a door.
GATEWAY_LAYERS: dict[str, int] = {
    "errors": 0, "params": 0, "ws_slices": 0, "state": 1, "ports": 2, "runner": 2,
    "http": 3, "modbus": 3, "serial": 3, "udp": 3, "rosbridge": 3, "foxglove": 3, "ros2": 3,
    "robot": 4, "fleet": 4, "front_ends": 4, "diagnostics": 4, "node": 4, "testing": 5,
    "__main__": 5,
}
DOORS = frozenset(k for k, v in GATEWAY_LAYERS.items() if v == 3)


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


@cache
def extensions() -> frozenset[str]:
    """The dotted names of the C extension modules (``zenros.tf._speedups``), from their
    sources: ``from . import _speedups`` imports that module, not its package."""
    out: set[str] = set()
    for package, tree in TREES.items():
        for path in tree.rglob("*.c"):
            out.add(".".join([package, *path.relative_to(tree).with_suffix("").parts]))
    return frozenset(out)


EXTENSIONS = extensions()


def statements(body: list[ast.stmt], typing_only: bool = False
               ) -> Iterator[tuple[ast.stmt, bool]]:
    """Every statement under ``body`` (imports are statements: expressions are not entered),
    each with whether it sits under an ``if TYPE_CHECKING``."""
    for node in body:
        yield node, typing_only
        under = typing_only
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            yield from statements(node.body, True)
            yield from statements(node.orelse, typing_only)
            continue
        for field in ("body", "orelse", "finalbody"):
            yield from statements(getattr(node, field, []), under)
        for handler in getattr(node, "handlers", []):
            yield from statements(handler.body, under)
        for case in getattr(node, "cases", []):
            yield from statements(case.body, under)


@cache
def parsed(path: Path) -> ast.Module:
    return ast.parse(path.read_text(), str(path))


def imports_of(name: str, path: Path, known: set[str], typing: bool = False) -> set[str]:
    """The zenros modules ``name`` imports at module level or in functions (and, with
    ``typing``, under ``if TYPE_CHECKING`` too). ``from pkg import mod`` imports ``pkg.mod``
    (and ``pkg``'s ``__init__`` only when a name is not a module of it)."""
    is_package = path.name == "__init__.py"
    compiled = EXTENSIONS
    submodules = known | compiled
    found: set[str] = set()
    for node, typing_only in statements(parsed(path).body):
        if typing_only and not typing:
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
            subs = [f"{mod}.{a.name}" for a in node.names]
            targets = ([] if all(s in submodules for s in subs) else [mod]) + subs
        for t in targets:
            if t in compiled:
                continue  # a C module imports nothing of ours
            while t and t not in known:
                t = t.rpartition(".")[0]
            if t and t != name:
                found.add(t)
    return found


def group(name: str) -> str:
    """``zenros.services.nav.planning.plan`` -> ``services.nav``; ``zenros.tf.buffer`` -> ``tf``;
    top-level modules of ``zenros`` are their own group; the gateway's sub-packages too
    (``zenros.services.gateway.http.api`` -> ``services.gateway.http``)."""
    parts = name.split(".")[1:]
    if not parts:
        return "zenros"
    if parts[:2] == ["services", "gateway"]:
        return ".".join(parts[:3])
    if parts[0] == "services":
        return ".".join(parts[:2])
    return parts[0]


def service(name: str) -> str:
    """The service a module belongs to (``services.nav``), or "" for the library."""
    parts = name.split(".")[1:]
    return ".".join(parts[:2]) if parts[:1] == ["services"] and len(parts) > 1 else ""


def gateway_part(name: str) -> str:
    """The gateway sub-package or top module ``name`` is in (``http``), or ""."""
    if not name.startswith(GATEWAY + "."):
        return ""
    return name[len(GATEWAY) + 1:].split(".")[0]


def wrong_way(graph: dict[str, set[str]]) -> list[str]:
    """The imports that break the layering: a service importing another service, and a
    gateway module importing a higher layer (a port or the state importing a door, a door
    importing the node, ...). Each as ``"importer -> imported: why"``."""
    out: list[str] = []
    for m, ts in sorted(graph.items()):
        for t in sorted(ts):
            sm, st = service(m), service(t)
            if sm and st and sm != st:
                out.append(f"{m} -> {t}: one service imports another")
            pm, pt = gateway_part(m), gateway_part(t)
            if pm and pt and pm != pt:
                rm, rt = GATEWAY_LAYERS.get(pm), GATEWAY_LAYERS.get(pt)
                if rm is None or rt is None:
                    out.append(f"{m} -> {t}: not in a gateway layer (scripts/import_graph.py "
                               "GATEWAY_LAYERS)")
                elif rt > rm:
                    out.append(f"{m} -> {t}: {pm} (layer {rm}) imports {pt} (layer {rt})")
    return out


def door_to_door(graph: dict[str, set[str]]) -> list[str]:
    """Gateway doors that import another door (allowed, but each is a coupling to know)."""
    return [f"{m} -> {t}" for m, ts in sorted(graph.items()) for t in sorted(ts)
            if gateway_part(m) in DOORS and gateway_part(t) in DOORS
            and gateway_part(m) != gateway_part(t)]


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(limit, 10_000))  # back to ``limit`` when done: the
    # caller's process may rely on it (a test's json.loads of deep text raising RecursionError)

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

    try:
        for v in sorted(graph):
            if v not in index:
                visit(v)
    finally:
        sys.setrecursionlimit(limit)
    return sorted(out, key=lambda c: (-len(c), c))


def library_circles(graph: dict[str, set[str]]) -> list[str]:
    """The import circles between modules of the library (``zenros``, not its services),
    type-checking imports included: a package's ``__init__`` counts as importing what it
    imports, so ``message`` -> ``msgs`` -> ``msgs.std_msgs`` -> ``message`` is one."""
    lib = {m: {t for t in ts if not service(t)} for m, ts in graph.items() if not service(m)}
    return [" -> ".join(c) for c in circles(lib)]


def service_circles(graph: dict[str, set[str]]) -> list[str]:
    """The import circles inside one service's package, type-checking imports included (a
    helper typed against the node that makes it, instead of a protocol of what it uses)."""
    inner = {m: {t for t in ts if service(t) == service(m)} for m, ts in graph.items()
             if service(m)}
    return [" -> ".join(c) for c in circles(inner)]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--modules", action="store_true", help="print every module's imports")
    ap.add_argument("--check", action="store_true",
                    help="print only the wrong-way imports; exit 1 if there are any")
    args = ap.parse_args()
    mods = modules()
    known = set(mods)
    def arrows(typing: bool) -> dict[str, set[str]]:
        return {m: imports_of(m, p, known, typing) for m, p in mods.items()}

    graph, typed = arrows(False), arrows(True)
    if args.check:
        bad = wrong_way(typed)
        print("\n".join(bad) or "no import points the wrong way")
        loops = library_circles(typed)
        print("\n".join(f"import circle: {c}" for c in loops) or "no import circle in the library")
        inside = service_circles(typed)
        print("\n".join(f"import circle: {c}" for c in inside)
              or "no import circle inside a service")
        return 1 if bad or loops or inside else 0
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
    print("\n## imports that point the wrong way (another service; a higher gateway layer)")
    print("\n".join(wrong_way(typed)) or "-")
    print("\n## the gateway's layers, lowest first (a module imports its own layer or lower)")
    layers: dict[int, list[str]] = defaultdict(list)
    for part, rank in GATEWAY_LAYERS.items():
        layers[rank].append(part)
    for rank in sorted(layers):
        print(f"{rank}: " + ", ".join(layers[rank]))
    print("\n## gateway doors importing another door")
    print("\n".join(door_to_door(graph)) or "-")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
