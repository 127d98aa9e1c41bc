"""`Reach`: when a query that got no reply is sent again, the one rule every client follows.

A Zenoh query finds its servers in the session's routing table when it is sent; when no
queryable matches, it ends at once with no reply (not after its timeout: eclipse-zenoh/zenoh
#2516). A server's liveliness token (what the graph lists) and its queryable are two
declarations that travel and are processed separately, with no order between them: a server
may declare them in either order (rmw_zenoh's and a restarting zenros server alike), and a link
made again re-declares the tokens before the queryables (eclipse-zenoh/zenoh #588). So a
session can list a server a moment before a query can reach it (seen beside a CPU hog: the
first query ended unanswered 0.7 ms after the graph listed the server). Being listed is no
proof of a route; only a query is. Every client (`Client.call`, `Client.call_async`, the
action client's send_goal and cancel, the CLI) therefore asks again, with growing pauses,
while the graph lists a server, for ``grace`` seconds at most, and gives up at once when the
graph lists none. A goal's client (send_goal, cancel) also waits ``relink`` seconds for a server
that was listed and left to be listed again: a link whose lease ran out on a starved box ends
the queries it carried unanswered and is made again within seconds, and a goal sent again under its
id is answered as it was the first time (`zenros.action.ActionServer`). And a goal's query that
got no answer at all within ``ANSWER_WAIT`` seconds is sent again under its id: on a starved box,
with links dropped and made again, Zenoh can lose a query without ending it, so that it waits
its whole timeout for nothing (issue 37.4: 3 of 120 fresh CLI goals beside two hogs waited 60 s).
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Awaitable, Callable
from typing import TypeVar

__all__ = ["ANSWER_WAIT", "REACH_GRACE", "RELINK", "Reach", "ask_while_listed", "ask_while_listed_async"]

REACH_GRACE = 1.0
"""Seconds a client asks again, by default, when no reply came but the graph lists a server."""

FIRST_PAUSE = 0.02
MAX_PAUSE = 0.2
RELINK = 10.0
"""Seconds a goal's client waits for its server to be listed again (`Reach`'s ``relink``):
Zenoh makes a lost link to a configured endpoint again within 2 s on a quiet box; beside ten
fresh CLIs and two CPU hogs on 2 cores, 3 s was not always enough (issue 37.4)."""
RELINK_POLL = 0.1
ANSWER_WAIT = 5.0
"""Seconds a goal's query waits for its first answer before the goal is sent again under its
id (`Reach.attempt`), doubling each time up to `MAX_ANSWER_WAIT`. A server answers the same goal
sent again as it did the first time, so a slow server costs nothing but the second query."""
MAX_ANSWER_WAIT = 20.0
MIN_ATTEMPT = 0.05

R = TypeVar("R")


class Reach:
    """The asking-again of one request: ``left()`` seconds for the next query, ``again()`` the
    pause before it (None: give up).

    Args:
        listed: whether the graph lists a server now.
        timeout: the whole request's timeout (seconds).
        grace: seconds (at most 90 % of ``timeout``) to ask again while no reply comes.
        relink: for a request the server may take twice (one that names itself, as a goal
            does by its id), seconds to wait for a server listed when the request started,
            and no longer listed, to be listed again before giving up (0: give up at once).
            A link between two processes whose lease ran out (a starved box: a receive side
            that stalled longer than the lease) ends the queries it carried, unanswered, and
            takes the server's tokens with it; Zenoh makes a configured link again within
            0.5-2 s.
        start: when the request started (`time.monotonic`; default now): a caller that sent
            its first query before making a `Reach` (a service call: none made while the
            first query is answered) counts that query's time.
    """

    def __init__(self, listed: Callable[[], bool], timeout: float,
                 grace: float = REACH_GRACE, relink: float = 0.0,
                 start: float | None = None) -> None:
        self._listed = listed
        self._timeout = timeout
        self._limit = min(grace, timeout * 0.9)
        self._start = self._grace_from = time.monotonic() if start is None else start
        self._pause = FIRST_PAUSE
        self._relink = relink
        self._was_listed = relink > 0 and listed()
        self._unlisted_at: float | None = None
        self._answer_wait = ANSWER_WAIT

    def elapsed(self) -> float:
        return time.monotonic() - self._start

    def left(self) -> float:
        """The timeout of the next query: what is left of the request's (10 ms at least)."""
        return max(0.01, self._timeout - self.elapsed())

    def attempt(self) -> float:
        """The timeout of the next query of a request that may be sent again while unanswered
        (a goal): `ANSWER_WAIT` s (doubling with each attempt, up to `MAX_ANSWER_WAIT`), or what is
        left of the request's timeout if less. Its query timing out with no answer means
        "send it again" while time is left (`resend`)."""
        wait = self._answer_wait
        self._answer_wait = min(wait * 2, MAX_ANSWER_WAIT)
        return min(wait, self.left())

    def resend(self) -> bool:
        """An attempt's query timed out with no answer: whether to send it again (time is
        left of the request's timeout)."""
        return self.left() > MIN_ATTEMPT

    def again(self) -> float | None:
        """A query ended with no reply: the pause before sending it again, or None when the
        grace is spent or the graph lists no server (with ``relink``: a server listed before
        has not been listed again within ``relink`` s). A server listed again gets a new
        grace: its routes come back after its tokens."""
        pause = self._pause
        now = time.monotonic()
        if self._listed():
            if self._unlisted_at is not None:  # listed again: a new grace for its routes
                self._grace_from, self._unlisted_at = now, None
            if now - self._grace_from + pause >= self._limit:
                return None
            self._was_listed = self._relink > 0
        elif not self._was_listed:
            return None
        else:  # listed when asked before: its link may be on its way back
            if self._unlisted_at is None:
                self._unlisted_at = now
            pause = max(pause, RELINK_POLL)
            if now - self._unlisted_at + pause > self._relink or self.left() <= pause:
                return None
        self._pause = min(pause * 2, MAX_PAUSE)
        return pause

    def ask(self, ask: Callable[[float], R | None]) -> R | None:
        """``ask(seconds_left)`` until it answers (not None), again after the pauses of
        `again`; None if nothing answered."""
        while True:
            answer = ask(self.left())
            if answer is not None:
                return answer
            pause = self.again()
            if pause is None:
                return None
            time.sleep(pause)

    async def ask_async(self, ask: Callable[[float], Awaitable[R | None]]) -> R | None:
        """`ask` on an event loop: ``await ask(seconds_left)``, pauses by ``asyncio.sleep``."""
        while True:
            answer = await ask(self.left())
            if answer is not None:
                return answer
            pause = self.again()
            if pause is None:
                return None
            await asyncio.sleep(pause)


def ask_while_listed(ask: Callable[[float], R | None], listed: Callable[[], bool],
                     timeout: float, grace: float = REACH_GRACE) -> R | None:
    """``ask(seconds_left)`` until it answers (not None), again while ``listed()`` for
    ``grace`` s at most (`Reach.ask`); None if nothing answered."""
    return Reach(listed, timeout, grace).ask(ask)


async def ask_while_listed_async(ask: Callable[[float], Awaitable[R | None]],
                                 listed: Callable[[], bool], timeout: float,
                                 grace: float = REACH_GRACE) -> R | None:
    """`ask_while_listed` for an event loop (`Reach.ask_async`)."""
    return await Reach(listed, timeout, grace).ask_async(ask)
