"""The launch files zenros carries, and finding one by its bare name (``zenros launch sim.yaml``).

deploy/ of the repository (launch files, the demo map) installs as the data package
``zenros.deploy`` (pyproject's package-dir and package-data): in an install it sits beside
the code, ``.../site-packages/zenros/deploy``; in an editable install (``pip install -e .``)
the code runs from the checkout, where it is ``deploy/`` beside ``shared/``. Both keep the
layout of the checkout, so a launch file's ``$(dirname)/../maps/...`` resolves in either.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import LaunchError

__all__ = ["deploy_dir", "describe", "find_launch_file", "launch_dir", "launch_files"]

_PACKAGE = Path(__file__).resolve().parents[1]  # site-packages/zenros, or the checkout's shared/
SUFFIXES = (".yaml", ".yml")


def deploy_dir() -> Path:
    """zenros's deploy/: ``zenros/deploy`` of an install, else the checkout's ``deploy/``."""
    installed = _PACKAGE / "deploy"
    checkout = _PACKAGE.parent / "deploy"
    if not installed.is_dir() and (_PACKAGE.parent / "pyproject.toml").is_file():
        return checkout
    return installed


def launch_dir() -> Path:
    """Where the launch files zenros carries are (``deploy/launch``)."""
    return deploy_dir() / "launch"


def launch_files() -> list[Path]:
    """The launch files zenros carries, by name."""
    folder = launch_dir()
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if p.suffix in SUFFIXES and p.is_file())


def find_launch_file(name: str | os.PathLike[str], cwd: Path | None = None) -> Path:
    """The launch file ``zenros launch NAME`` runs.

    A file at NAME (absolute, or relative to ``cwd``, default the current directory) is that
    file, as is any NAME with a directory part. A bare name of no file here is looked up among
    the launch files zenros carries, as given or with ``.yaml`` added (``sim.yaml``, ``sim``).

    Raises:
        LaunchError: a bare name found nowhere; the message names the launch files there are.
    """
    path = Path(name)
    here = path if path.is_absolute() else (cwd or Path.cwd()) / path
    if here.is_file() or len(path.parts) != 1 or path.name in (".", ".."):
        return here
    for candidate in (path.name, path.name + ".yaml"):
        found = launch_dir() / candidate
        if found.is_file():
            return found
    known = ", ".join(p.name for p in launch_files()) or "none"
    raise LaunchError(
        f"launch file not found: {name} is neither a file here nor one of zenros's launch"
        f" files ({known}; `zenros launch --list` describes them)"
    )


def describe(file: Path) -> str:
    """The first sentence of a launch file's leading comment (its one-line description)."""
    words: list[str] = []
    try:
        lines = file.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return ""
    for line in lines:
        text = line.strip()
        if not text.startswith("#"):
            break
        text = text.lstrip("#").strip()
        if not text:
            if words:
                break
            continue
        words.append(text)
        if text.endswith("."):
            break
    sentence = " ".join(words)
    end = sentence.find(". ")
    return sentence if end < 0 else sentence[: end + 1]
