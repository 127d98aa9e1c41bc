"""`call_when_reachable`: a server in the graph whose first queries end unanswered (a fresh
session routes to it a moment after it sees its token) is asked again; one not in the graph is
not waited for."""

from __future__ import annotations

from typing import Any, cast

import pytest
from zenros.cli.common import call_when_reachable
from zenros.errors import ServiceUnavailableError
from zenros.msgs.std_srvs import Trigger
from zenros.rpc import Client


class FlakyClient:
    """Raises ServiceUnavailableError ``misses`` times, then answers; ``listed``: whether
    the graph shows its server."""

    def __init__(self, misses: int, listed: bool = True) -> None:
        self.misses = misses
        self.listed = listed
        self.calls: list[float] = []

    def call(self, request: Any, timeout: float = 5.0) -> str:
        self.calls.append(timeout)
        if len(self.calls) <= self.misses:
            raise ServiceUnavailableError("no server for service /x")
        return "answer"

    def service_is_ready(self) -> bool:
        return self.listed


def _call(client: FlakyClient, timeout: float) -> Any:
    return call_when_reachable(cast(Client, client), Trigger.Request(), timeout)


def test_a_listed_server_that_missed_the_first_queries_answers() -> None:
    client = FlakyClient(misses=3)
    assert _call(client, 5.0) == "answer"
    assert len(client.calls) == 4
    assert all(0.1 <= t <= 5.0 for t in client.calls)
    assert client.calls == sorted(client.calls, reverse=True)  # each gets what is left


def test_a_server_not_in_the_graph_is_not_waited_for() -> None:
    client = FlakyClient(misses=10, listed=False)
    with pytest.raises(ServiceUnavailableError, match="no server"):
        _call(client, 5.0)
    assert len(client.calls) == 1


def test_a_listed_server_that_never_answers_fails_within_the_timeout() -> None:
    client = FlakyClient(misses=1000)
    with pytest.raises(ServiceUnavailableError, match="no server"):
        _call(client, 0.5)
    assert 2 <= len(client.calls) < 20
