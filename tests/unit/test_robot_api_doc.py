"""The robot API's section numbers cited in the code ("§6.7") point into docs/robot-api.md:
every module that cites one names the page, and every section it cites is a heading there."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "robot-api.md"
CITED = re.compile(r"§(\d+(?:\.\d+)?)")
HEADING = re.compile(r"^#{2,3} (\d+(?:\.\d+)?)\.? ", re.MULTILINE)


def _citing_files() -> dict[Path, str]:
    files = [p for d in ("shared", "services", "tests", "bench", "scripts")
             for p in sorted((ROOT / d).rglob("*.py"))]
    files += [p for p in sorted((ROOT / "docs").glob("*.md")) if p != DOC]
    texts = {p: p.read_text() for p in files}
    return {p: t for p, t in texts.items() if "§" in t}


def test_every_citing_module_names_the_page() -> None:
    citing = _citing_files()
    assert len(citing) > 40  # the gateway, tasks, nav's connections, the messages, their tests
    missing = [str(p.relative_to(ROOT)) for p, t in citing.items() if "docs/robot-api.md" not in t]
    assert not missing, missing


def test_every_cited_section_is_in_the_page() -> None:
    sections = set(HEADING.findall(DOC.read_text()))
    assert {"0", "1.2", "6.7", "19"} <= sections
    unknown = sorted({f"{p.relative_to(ROOT)}: §{n}" for p, t in _citing_files().items()
                      for n in CITED.findall(t) if n not in sections})
    assert not unknown, unknown


def test_nothing_cites_the_original_spec() -> None:
    """The manual's translation (``specs/robot-api.md``) is not in the repository."""
    stale = [str(p.relative_to(ROOT)) for p, t in _citing_files().items()
             if p != Path(__file__) and "specs/robot-api.md" in t]
    assert not stale, stale
