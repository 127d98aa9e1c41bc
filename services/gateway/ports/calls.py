"""`call_port`: one service call of a port, its failures said in the robot's terms (the port
errors of `..errors`): no server, no answer in time, or the server's refusal. `Lazy`: an
endpoint made at its first use.

A fleet gateway holds every port once per robot, and every endpoint is a declaration each
process of the Zenoh network learns: ports of the operations a robot's clients rarely use make
their endpoints when first used, not at start."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Generic, TypeVar

from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.rpc import Client

from ..errors import Failed, NoAnswer, PortError

__all__ = ["Lazy", "call_port"]

Q = TypeVar("Q")
S = TypeVar("S")
T = TypeVar("T")


class Lazy(Generic[T]):
    """``make()``'s result, made at the first `get` (once, whichever thread asks first)."""

    def __init__(self, make: Callable[[], T]) -> None:
        self._make = make
        self._value: T | None = None
        self._lock = threading.Lock()

    @property
    def made(self) -> bool:
        return self._value is not None

    def get(self) -> T:
        value = self._value
        if value is None:
            with self._lock:
                if self._value is None:
                    self._value = self._make()
                value = self._value
        return value


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
