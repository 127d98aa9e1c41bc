"""The shell commands of README.md and docs/*.md, as the doc check runs them.

Every fenced ```bash or ```sh block is read line by line (``\\`` continuations joined, comment
lines and blank lines left out). An HTML comment on the lines just before a block steers it:

* ``<!-- doc-check: skip REASON -->``: the block is not run (hardware, root, installs,
  long-running programs, services the sim does not launch).
* ``<!-- doc-check: skip-line PREFIX -->`` (one per line, any number): the block's commands
  that start with PREFIX are not run.
* ``<!-- doc-check: fleet -->``: the block runs against a launched fleet
  (``deploy/launch/fleet.yaml robots:=3`` and its one gateway) instead of the sim.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["Block", "Command", "doc_blocks", "doc_pages"]

_FENCE = re.compile(r"^```(\w*)\s*$")
_MARKER = re.compile(r"^<!--\s*doc-check:\s*(skip-line|skip|fleet)\b\s*(.*?)\s*-->\s*$")
SHELLS = ("bash", "sh")


@dataclass(frozen=True)
class Command:
    """One command line of a block, with where it is."""

    page: str
    line: int
    text: str

    @property
    def where(self) -> str:
        return f"{self.page}:{self.line}"


@dataclass
class Block:
    """A shell block of a page and what its markers say."""

    page: str
    line: int
    commands: list[Command] = field(default_factory=list)
    skip: str | None = None
    skip_lines: list[str] = field(default_factory=list)
    fleet: bool = False  # runs against a launched fleet, not the sim

    def runnable(self) -> list[Command]:
        if self.skip is not None:
            return []
        return [c for c in self.commands
                if not any(c.text.startswith(p) for p in self.skip_lines)]


def doc_pages(root: Path) -> list[Path]:
    """README.md and every page under docs/."""
    return [root / "README.md", *sorted((root / "docs").glob("*.md"))]


def doc_blocks(page: Path, root: Path) -> list[Block]:
    """The shell blocks of one page, with their markers applied."""
    name = str(page.relative_to(root))
    lines = page.read_text(encoding="utf-8").splitlines()
    blocks: list[Block] = []
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i].strip())
        if not m:
            i += 1
            continue
        lang, start = m.group(1), i
        j = i + 1
        while j < len(lines) and not lines[j].strip().startswith("```"):
            j += 1
        if lang in SHELLS:
            block = Block(name, start + 1)
            _apply_markers(block, lines, start)
            block.commands = _commands(name, lines, start + 1, j)
            blocks.append(block)
        i = j + 1
    return blocks


def _apply_markers(block: Block, lines: list[str], fence: int) -> None:
    k = fence - 1
    while k >= 0 and (not lines[k].strip() or _MARKER.match(lines[k].strip())):
        m = _MARKER.match(lines[k].strip())
        if m and m.group(1) == "skip":
            block.skip = m.group(2) or "marked skip"
        elif m and m.group(1) == "fleet":
            block.fleet = True
        elif m:
            block.skip_lines.append(m.group(2))
        k -= 1


def _commands(page: str, lines: list[str], first: int, end: int) -> list[Command]:
    out: list[Command] = []
    text, at = "", 0
    for n in range(first, end):
        raw = lines[n].strip()
        if not text:
            if not raw or raw.startswith("#"):
                continue
            at = n + 1
            raw = raw.removeprefix("$ ")
        if raw.endswith("\\"):
            text += raw[:-1].rstrip() + " "
            continue
        text += raw
        out.append(Command(page, at, text.strip()))
        text = ""
    if text:
        out.append(Command(page, at, text.strip()))
    return out
