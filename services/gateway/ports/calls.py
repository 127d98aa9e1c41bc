"""`call_port`: one service call of a port, its failures said in the robot's terms (the port
errors of `..errors`): no server, no answer in time, or the server's refusal."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.rpc import Client

from ..errors import Failed, NoAnswer, PortError

__all__ = ["call_port"]

Q = TypeVar("Q")
S = TypeVar("S")


def _failed(client: Client[Q, S]) -> Callable[[ServiceError], PortError]:
    return lambda exc: Failed(f"{client.name} failed: {exc}")


async def call_port(client: Client[Q, S], request: Q, timeout: float,
                    absent: Callable[[], PortError], who: str = "",
                    failed: Callable[[ServiceError], PortError] | None = None) -> S:
    """``client``'s answer to ``request``; ``absent()`` when no server is in the graph,
    `NoAnswer` after ``timeout`` s (naming ``who`` when given), ``failed(exc)`` (default: a
    `Failed`) when the server answers with an error."""
    try:
        return await client.call_async(request, timeout)
    except ServiceUnavailableError:
        raise absent() from None
    except ZenrosTimeout:
        what = f"{who} did not answer {client.name}" if who else f"{client.name} did not answer"
        raise NoAnswer(f"{what} within {timeout:g} s") from None
    except ServiceError as exc:
        raise (failed or _failed(client))(exc) from exc
