#!/usr/bin/env python3
"""Reach-ins across objects, counted with ast: an attribute access ``x._name`` (a single
leading underscore) where ``x`` is not ``self``, ``cls`` or ``super()``. Each is a place where
one object reads or changes another's private state (docs/architecture.md: one owner for
each piece of state).

    python3 scripts/reach_ins.py                 # the total and the files with the most
    python3 scripts/reach_ins.py -v shared/action # every one, in these folders
"""

from __future__ import annotations

import argparse
import ast
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _owner_is_self(value: ast.expr) -> bool:
    if isinstance(value, ast.Name):
        return value.id in ("self", "cls")
    return (isinstance(value, ast.Call) and isinstance(value.func, ast.Name)
            and value.func.id == "super")


def reach_ins(path: Path) -> list[tuple[int, str]]:
    """(line, expression) of every reach-in in one file."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if (isinstance(node, ast.Attribute) and node.attr.startswith("_")
                and not node.attr.startswith("__") and not _owner_is_self(node.value)):
            found.append((node.lineno, ast.unparse(node)))
    return sorted(found)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folders", nargs="*", default=["shared", "services"])
    ap.add_argument("-v", "--verbose", action="store_true", help="list every reach-in")
    args = ap.parse_args()
    per_file: Counter[str] = Counter()
    for folder in args.folders:
        for path in sorted((ROOT / folder).rglob("*.py")):
            name = str(path.relative_to(ROOT))
            for line, expr in reach_ins(path):
                per_file[name] += 1
                if args.verbose:
                    print(f"{name}:{line}: {expr}")
    print(f"{sum(per_file.values())} reach-ins in {', '.join(args.folders)}")
    for name, count in per_file.most_common(10):
        print(f"{count:5d}  {name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
