"""Shared fixtures: isolated Zenoh sessions on loopback, a router process, node factories."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from zenros.context import Context
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import Proc, free_port, linked_contexts, unique_prefix, wait_for


@pytest.fixture
def prefix() -> str:
    return unique_prefix()


@pytest.fixture
def ctx_pair(prefix: str) -> Iterator[list[Context]]:
    """Two sessions (as two processes would have) meshed on loopback, one key prefix."""
    with linked_contexts(2, prefix) as ctxs:
        yield ctxs


@pytest.fixture
def make_node(ctx_pair: list[Context]) -> Iterator[Callable[..., Any]]:
    """``make_node(name, side=0|1, cls=Node, **kw)``: nodes closed at teardown."""
    nodes: list[Node] = []

    def factory(name: str, side: int = 0, cls: type[Node] = Node, **kw: Any) -> Any:
        node = cls(name, context=ctx_pair[side], **kw)
        nodes.append(node)
        return node

    yield factory
    for n in reversed(nodes):
        n.close()


@pytest.fixture
def router() -> Iterator[str]:
    """A real Zenoh router process on a free loopback port; yields its endpoint."""
    port = free_port()
    endpoint = f"tcp/127.0.0.1:{port}"
    proc = Proc([sys.executable, "-m", "zenros.router", "-l", endpoint])
    try:
        assert proc.wait_line("router listening", 15), proc.output
        yield endpoint
    finally:
        proc.stop()


@pytest.fixture
def observer(router: str, prefix: str) -> Iterator[Context]:
    """A session of the test's own on the ``router``, to watch the graph and make calls."""
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    try:
        yield ctx
    finally:
        ctx.close()


@pytest.fixture
def procs() -> Iterator[list[Proc]]:
    """Child processes a test starts; each is stopped (SIGINT, then SIGKILL) at teardown."""
    started: list[Proc] = []
    yield started
    for p in started:
        p.stop()


__all__ = ["wait_for"]
