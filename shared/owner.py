"""`Owner`: what an object created on a node uses of it (typed so, not as `zenros.Node`).

`zenros.node` imports the modules that define those objects (action servers and clients,
the parameter backend); they type their node with a protocol built on this one, so no
import points back at `zenros.node`.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Protocol, TypeVar

if TYPE_CHECKING:
    from .context import Context

__all__ = ["Closable", "Owner"]


class Closable(Protocol):
    """What a node can own (`Node.own`, `Node.add_waitable`): anything with ``close()``."""

    def close(self) -> None: ...


E = TypeVar("E", bound=Closable)


class Owner(Protocol):
    """The node an object is created on, and closed with."""

    @property
    def fqn(self) -> str: ...

    @property
    def context(self) -> Context: ...

    @property
    def logger(self) -> logging.Logger: ...

    def add_waitable(self, endpoint: E) -> E: ...
