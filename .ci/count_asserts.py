#!/usr/bin/env python3
"""Count tests and assertions under tests/ (issue 23: coverage must not shrink when tests move).

Counts, via ast over every tests/**/*.py: `assert` statements, `pytest.raises(...)` /
`pytest.warns(...)` calls, and test functions (def test_*). Run: python3 .ci/count_asserts.py [root]
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path


def count(root: Path) -> dict[str, int]:
    totals = {"files": 0, "test_functions": 0, "assert": 0, "pytest.raises": 0, "pytest.warns": 0}
    for path in sorted(root.rglob("*.py")):
        if ".venv" in path.parts:
            continue
        tree = ast.parse(path.read_text(), str(path))
        totals["files"] += 1
        for node in ast.walk(tree):
            if isinstance(node, ast.Assert):
                totals["assert"] += 1
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if node.name.startswith("test"):
                    totals["test_functions"] += 1
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
                f = node.func
                if isinstance(f.value, ast.Name) and f.value.id == "pytest":
                    if f.attr in ("raises", "warns"):
                        totals[f"pytest.{f.attr}"] += 1
    return totals


if __name__ == "__main__":
    root = Path(sys.argv[1] if len(sys.argv) > 1 else "tests")
    for k, v in count(root).items():
        print(f"{k:16} {v}")
