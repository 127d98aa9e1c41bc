"""`ActionHost`: what an action server or client uses of the node that owns it (a `zenros.Node`).

Typed against this protocol, `zenros.action` does not import `zenros.node`, which imports it
to create servers and clients: the imports point one way.
"""

from __future__ import annotations

from typing import Protocol

from ..msgs.builtin_interfaces import Time
from ..owner import Owner

__all__ = ["ActionHost"]


class ActionHost(Owner, Protocol):
    """The node an `ActionServer` or `ActionClient` is created on."""

    def resolve_name(self, name: str, kind: str = "topic") -> str: ...

    def now(self) -> Time: ...
