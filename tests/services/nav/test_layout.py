"""nav's packages import one way (docs/architecture.md, "nav: packages and imports"): a module
imports its own package and the layers below it, never a layer above or beside it, and no
other service. Read with ast by scripts/import_graph.py, so nothing is imported to check it."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

ROOT = Path(__file__).resolve().parents[3]
NAV = "zenros.services.nav"
LAYERS: list[set[str]] = [
    {"maps", "localization", "refusals"},
    {"costmap"},
    {"planning"},
    {"motion"},
    {"people"},
    {"core"},
    {"params"},
    {"actions", "diagnostics"},
    {"schedule_link"},
    {"node"},
    {"__main__"},
]
"""Bottom to top; each name is a sub-package of nav or a top-level module."""


def _graph_script() -> ModuleType:
    spec = importlib.util.spec_from_file_location("import_graph", ROOT / "scripts/import_graph.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _part(module: str) -> str:
    """``zenros.services.nav.planning.plan`` -> ``planning``; the package itself -> ``""``."""
    return module.removeprefix(NAV).lstrip(".").partition(".")[0]


def _layer(part: str) -> int:
    for i, names in enumerate(LAYERS):
        if part in names:
            return i
    raise AssertionError(f"{NAV}.{part} is in no layer of LAYERS: place it ({LAYERS})")


def _nav_imports() -> dict[str, set[str]]:
    graph = _graph_script()
    mods = graph.modules()
    known = set(mods)
    return {m: graph.imports_of(m, p, known, typing=True)
            for m, p in mods.items() if m == NAV or m.startswith(NAV + ".")}


def test_every_nav_module_is_in_a_layer() -> None:
    nav = _nav_imports()
    assert f"{NAV}.planning.plan" in nav and f"{NAV}.node" in nav  # the walk found nav
    for m in nav:
        if m != NAV:
            _layer(_part(m))


def test_nav_imports_point_down_only() -> None:
    wrong = []
    for m, targets in sorted(_nav_imports().items()):
        src = _part(m)
        for t in sorted(targets):
            if not t.startswith(NAV + "."):
                continue
            dst = _part(t)
            # (the package's own __init__ imports nothing of nav)
            if m == NAV or (dst != src and _layer(dst) >= _layer(src)):
                wrong.append(f"{m} -> {t}")
    assert not wrong, "imports up or sideways between nav's packages:\n" + "\n".join(wrong)


def test_nav_imports_no_other_service() -> None:
    others = [f"{m} -> {t}" for m, ts in _nav_imports().items() for t in ts
              if t.startswith("zenros.services.") and not t.startswith(NAV)]
    assert not others, others


def test_no_two_nav_modules_share_a_stem_beside_each_other() -> None:
    """The clashes issue #22 named (planner/ beside planning.py, costmap/ beside costmaps.py,
    coverage.py beside coverage_srv.py): in one folder no name is another's prefix."""
    clashes = []
    for folder in [ROOT / "services/nav", *(ROOT / "services/nav").glob("*/")]:
        names = sorted({p.stem for p in folder.iterdir()
                        if p.stem != "__init__" and p.suffix in ("", ".py")
                        and not p.name.startswith("__")})
        clashes += [f"{folder.name}/: {a} ~ {b}" for a in names for b in names
                    if a != b and b.startswith(a.rstrip("s"))]
    assert not clashes, clashes
