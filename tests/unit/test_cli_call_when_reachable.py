"""`zenros.reach.ask_while_listed` (what every client asks through: `Client.call` and
`call_async`, the action client, the CLI's ``service call``, ``action send_goal`` and ``task``
verbs): a server in the graph whose first queries end unanswered (a fresh
session routes to it a moment after it sees its token) is asked again; one not in the graph is
not waited for."""

from __future__ import annotations

from zenros.reach import ask_while_listed


class FlakyServer:
    """Answers None ``misses`` times, then "answer"; ``listed``: whether the graph shows it."""

    def __init__(self, misses: int, listed: bool = True) -> None:
        self.misses = misses
        self.listed = listed
        self.calls: list[float] = []

    def ask(self, left: float) -> str | None:
        self.calls.append(left)
        return None if len(self.calls) <= self.misses else "answer"


def _ask(server: FlakyServer, timeout: float, grace: float | None = None) -> str | None:
    return ask_while_listed(server.ask, lambda: server.listed, timeout,
                            timeout if grace is None else grace)


def test_a_listed_server_that_missed_the_first_queries_answers() -> None:
    server = FlakyServer(misses=3)
    assert _ask(server, 5.0) == "answer"
    assert len(server.calls) == 4
    assert all(0.01 <= t <= 5.0 for t in server.calls)
    assert server.calls == sorted(server.calls, reverse=True)  # each gets what is left


def test_a_server_not_in_the_graph_is_not_waited_for() -> None:
    server = FlakyServer(misses=10, listed=False)
    assert _ask(server, 5.0) is None
    assert len(server.calls) == 1


def test_a_listed_server_that_never_answers_ends_within_the_timeout() -> None:
    server = FlakyServer(misses=1000)
    assert _ask(server, 0.5) is None
    assert 2 <= len(server.calls) < 20


def test_the_grace_bounds_the_asking_again() -> None:
    server = FlakyServer(misses=1000)
    assert _ask(server, 5.0, grace=0.1) is None
    assert 2 <= len(server.calls) < 6
