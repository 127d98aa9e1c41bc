"""The gateway's doors as its node runs them (`front_ends.FrontEnds`): started in order,
stopped in reverse, each stop whatever the others do; coroutine steps on the gateway's loop,
plain ones where the node calls them."""

from __future__ import annotations

import asyncio
import logging
import threading
from collections.abc import Iterator

import httpx
import pytest
from starlette.responses import PlainTextResponse
from starlette.types import Receive, Scope, Send
from zenros.services.gateway.front_ends import AsgiServer, Door, FrontEnds
from zenros.services.gateway.runner import AsyncRunner


@pytest.fixture
def runner() -> Iterator[AsyncRunner]:
    r = AsyncRunner("test-front-ends")
    yield r
    r.stop()


def test_front_ends_stop_in_reverse_even_when_one_fails(runner: AsyncRunner,
                                                        caplog: pytest.LogCaptureFixture) -> None:
    said: list[str] = []
    loop_thread: list[bool] = []

    async def on_loop(what: str) -> None:
        loop_thread.append(asyncio.get_running_loop() is runner.loop)
        said.append(what)

    def broken() -> None:
        said.append("stop b")
        raise OSError("port gone")

    ends = FrontEnds(runner, logging.getLogger("test.front_ends"))
    ends.start(Door("a", lambda: on_loop("start a"), lambda: on_loop("stop a")))
    ends.start(Door("b", lambda: said.append("start b"), broken))
    ends.start(Door("c", lambda: on_loop("start c"), lambda: said.append("stop c")))
    assert said == ["start a", "start b", "start c"]
    with caplog.at_level(logging.ERROR):
        ends.stop()
    assert said[3:] == ["stop c", "stop b", "stop a"]
    assert "stopping the b front end failed" in caplog.text
    assert all(loop_thread) and len(loop_thread) == 3
    assert not ends.started
    ends.stop()  # twice is nothing
    assert len(said) == 6


def test_a_front_end_whose_start_fails_is_not_stopped(runner: AsyncRunner) -> None:
    said: list[str] = []

    async def refuse() -> None:
        raise OSError("address in use")

    ends = FrontEnds(runner, logging.getLogger("test.front_ends"))
    ends.start(Door("a", lambda: said.append("start a"), lambda: said.append("stop a")))
    with pytest.raises(OSError, match="in use"):
        ends.start(Door("b", refuse, lambda: said.append("stop b")))
    ends.stop()
    assert said == ["start a", "stop a"]


async def _hello(scope: Scope, receive: Receive, send: Send) -> None:
    await PlainTextResponse(f"hello from {threading.current_thread().name}")(scope, receive, send)


def test_an_asgi_server_serves_until_stopped(runner: AsyncRunner) -> None:
    server = AsgiServer("hello", _hello, "127.0.0.1", 0)
    assert server.port > 0  # bound when made: the port is known before it starts
    ends = FrontEnds(runner, logging.getLogger("test.front_ends"))
    ends.start(server)
    url = f"http://127.0.0.1:{server.port}/"
    assert httpx.get(url, timeout=5).text == "hello from test-front-ends"
    ends.stop()
    with pytest.raises(httpx.ConnectError):
        httpx.get(url, timeout=5)
