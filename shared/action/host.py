"""`ActionHost`: what an action server or client uses of the node that owns it (a `zenros.Node`).

Typed against this protocol, `zenros.action` does not import `zenros.node`, which imports it
to create servers and clients: the imports point one way.
"""

from __future__ import annotations

import logging
from typing import Protocol, TypeVar

from ..context import Context
from ..msgs.builtin_interfaces import Time

__all__ = ["ActionHost"]


class _Closable(Protocol):
    def close(self) -> None: ...


E = TypeVar("E", bound=_Closable)


class ActionHost(Protocol):
    """The node an `ActionServer` or `ActionClient` is created on."""

    @property
    def fqn(self) -> str: ...

    @property
    def context(self) -> Context: ...

    @property
    def logger(self) -> logging.Logger: ...

    def resolve_name(self, name: str, kind: str = "topic") -> str: ...

    def add_waitable(self, endpoint: E) -> E: ...

    def now(self) -> Time: ...
