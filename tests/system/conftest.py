"""Rigs shared by the system tests.

- ``launch_text``: ``launch_text(yaml, *flags)`` launches a launch file's text with its own
  router (a free port) and key prefix, waits for the router, and yields the launcher and a
  context on that router; both are stopped at teardown.
- ``plain_wheel``: zenros built once per session as ``pip install <checkout>`` builds it (a
  wheel of a clean copy of the checkout: build isolation, the C modules compiled). The plain
  installs of test_install.py and test_user_install.py both install it, so the C modules are
  compiled once, not once per test.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager
from pathlib import Path

import pytest
from checkout import build_wheel
from zenros.context import Context
from zenros.session import SessionOptions
from zenros.testing import Proc, free_port, unique_prefix

LaunchText = Callable[..., AbstractContextManager[tuple[Proc, Context]]]


@pytest.fixture
def launch_text(tmp_path: Path) -> LaunchText:
    @contextmanager
    def launch(text: str, *flags: str) -> Iterator[tuple[Proc, Context]]:
        endpoint = f"tcp/127.0.0.1:{free_port()}"
        prefix = unique_prefix()
        (tmp_path / "launch.yaml").write_text(text)
        proc = Proc([sys.executable, "-m", "zenros.cli", "launch", str(tmp_path / "launch.yaml"),
                     "--data-dir", str(tmp_path / "home"), *flags],
                    env={"ZENROS_CONNECT": endpoint, "ZENROS_PREFIX": prefix})
        ctx: Context | None = None
        try:
            assert proc.wait_line("started a Zenoh router", 60), proc.output
            ctx = Context(SessionOptions(connect=[endpoint]), prefix=prefix)
            yield proc, ctx
        finally:
            if ctx is not None:
                ctx.close()
            proc.stop(timeout=20)

    return launch


@pytest.fixture(scope="session")
def plain_wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_wheel(tmp_path_factory.mktemp("wheel"))
