"""A clean copy of the checkout, and the wheel ``pip install <checkout>`` builds from it (for
the install tests: test_install.py, test_user_install.py; the wheel is conftest.py's
``plain_wheel``)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

__all__ = ["NOT_CLONED", "ROOT", "build_wheel", "clean_copy"]

ROOT = Path(__file__).resolve().parents[2]
# What a clean clone lacks: build output, venvs, caches.
NOT_CLONED = shutil.ignore_patterns(".git", ".venv", "venv", "build", "dist", "*.egg-info",
                                    "__pycache__", "*.so", "*.pyc", ".*_cache", "test-artifacts")


def clean_copy(dest: Path) -> Path:
    """The checkout's files as a clean clone has them, at ``dest`` (a build writes into its
    source, and the running suite keeps its own)."""
    shutil.copytree(ROOT, dest, ignore=NOT_CLONED, symlinks=True)
    return dest


def build_wheel(tmp: Path) -> Path:
    """The wheel ``pip install <checkout>`` builds and then installs: ``pip wheel`` is that
    step alone (the same isolated build of the same source, the C modules compiled)."""
    src = clean_copy(tmp / "zenros")
    dist = tmp / "dist"
    r = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--disable-pip-version-check",
         "-w", str(dist), str(src)],
        cwd=tmp, capture_output=True, text=True, timeout=380, check=False,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    wheels = sorted(dist.glob("zenros-*.whl"))
    assert len(wheels) == 1, (wheels, r.stdout[-2000:])
    return wheels[0]
