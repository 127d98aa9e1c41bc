"""Rigs shared by the system tests.

- ``plain_wheel``: zenros built once per session as ``pip install <checkout>`` builds it (a
  wheel of a clean copy of the checkout: build isolation, the C modules compiled). The plain
  installs of test_install.py and test_user_install.py both install it, so the C modules are
  compiled once, not once per test.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from checkout import build_wheel


@pytest.fixture(scope="session")
def plain_wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_wheel(tmp_path_factory.mktemp("wheel"))
