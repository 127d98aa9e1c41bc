"""`Capability`: a group of rosbridge ops that one client's session runs, as rosbridge_suite's
``capability.py``: each names the op codes it answers (``ops``) and keeps its own state (the
client's subscriptions, the services it serves, its goals); the session (`client.py`)
registers them, hands each frame to the op's handler and closes them when the client goes.

A new op goes in the capability of its kind (`ops_topics.TopicOps`, `ops_services.ServiceOps`,
`ops_actions.ActionOps`), or in a new module that copies one of them: a `Capability`
subclass with ``ops = {<Frame type>: "<method>"}`` (the frame type, tagged with the op code,
in `frames.py`), listed in `client.CAPABILITIES`.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import Any, ClassVar, Protocol

from .bridge import Bridge, Encode
from .frames import Frame, op_of
from .outbox import Outbox

__all__ = ["Capability", "OpHandler", "Session"]

OpHandler = Callable[[Any], None]
"""An op's handler: takes the request frame (its op's `frames.Frame` type); raises
`frames.OpError` (and the like) to have it reported with the frame's id."""


class Session(Protocol):
    """One client's session as its capabilities see it (`client.ClientProtocol`): where
    replies go, how errors are reported, and the bridge `Sink` its topics are fed to."""

    bridge: Bridge
    outbox: Outbox
    closed: bool

    def send(self, obj: dict[str, Any], fragment_size: int = 0) -> None: ...

    def report(self, level: str, message: str, mid: Any = None) -> None: ...

    def spawn(self, coro: Awaitable[Any]) -> None: ...

    def deliver(self, topic: str, encode: Encode) -> None: ...

    def format_of(self, topic: str) -> str: ...


class Capability:
    """Ops of one kind for one client: ``ops`` maps each op's frame type (a `frames.Frame`
    tagged with the op code) to the name of the method answering it."""

    ops: ClassVar[dict[type[Frame], str]] = {}

    def __init__(self, session: Session) -> None:
        self.session = session
        self.bridge = session.bridge

    def handlers(self) -> dict[str, tuple[type[Frame], OpHandler]]:
        """The op codes this capability answers, with their frame types and handlers."""
        return {op_of(kind): (kind, getattr(self, name)) for kind, name in self.ops.items()}

    def send(self, obj: dict[str, Any], fragment_size: int = 0) -> None:
        """Queue a reply frame to the client."""
        self.session.send(obj, fragment_size)

    def report(self, level: str, message: str, mid: Any = None) -> None:
        self.session.report(level, message, mid)

    def spawn(self, coro: Awaitable[Any]) -> None:
        """Run ``coro`` on the loop for as long as the client stays."""
        self.session.spawn(coro)

    def close(self) -> None:
        """Release what this capability holds for the client (on disconnect)."""
