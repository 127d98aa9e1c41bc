"""Context.close: a Zenoh session that will not close in time does not fail the process."""

from __future__ import annotations

from typing import Any

import pytest
import zenoh

from zenros.context import Context
from zenros.session import SessionOptions


class _SlowToClose:
    """Stands in for the session zenoh returns: closing it times out, as on a starved box."""

    def __init__(self, real: zenoh.Session) -> None:
        self.real = real
        self.closes = 0

    def close(self) -> None:
        self.closes += 1
        self.real.close()  # type: ignore[no-untyped-call]
        raise zenoh.ZError("close operation timed out! at zenoh/src/api/builders/close.rs:135.")

    def __getattr__(self, name: str) -> Any:
        return getattr(self.real, name)


def test_a_session_close_that_times_out_is_logged_not_raised(
        caplog: pytest.LogCaptureFixture) -> None:
    ctx = Context(SessionOptions(connect=[], listen=["tcp/127.0.0.1:0"]), prefix="ztclose")
    slow = _SlowToClose(ctx.session)
    ctx.session = slow  # type: ignore[assignment]
    with caplog.at_level("WARNING", logger="zenros.context"):
        ctx.close()  # the CLI's last step: before, zenoh's ZError made it exit 1
    assert slow.closes == 1 and ctx.closed
    assert "did not close in time" in caplog.text
    ctx.close()  # closing again is a no-op
    assert slow.closes == 1
