"""`PeopleLink`: person following over nav's ``follow/set`` and ``follow/status``
(zenros_msgs/SetFollow, GetFollowStatus), and the greeting: while on, nav's leg detector's
people (``people/detections``) go through a `Greeter` and a person coming near is greeted
by ``speak``."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, Literal

from zenros.msgs.std_msgs import Empty
from zenros.msgs.zenros_msgs import (
    FollowStatus,
    GetFollowStatus,
    GetFollowStatusResponse,
    PersonDetections,
    SetFollow,
    SetFollowRequest,
    SetFollowResponse,
)
from zenros.node import Node

from ..errors import Conflict, Unavailable
from ..state.greeter import DEFAULT_GREETING, Greeter
from .calls import Lazy, call_port

__all__ = ["PeopleLink"]


def _absent() -> Unavailable:
    return Unavailable("no person following: nav's follow/set is not in the graph (nav is "
                       "not running)")


class PeopleLink:
    """Calls nav's following services and greets for the doors."""

    def __init__(self, node: Node, speak: Callable[[str], object],
                 now: Callable[[], float], timeout: float = 5.0) -> None:
        self.node = node
        self.speak = speak
        self.now = now
        self.timeout = timeout
        self._set = Lazy(lambda: node.create_client(SetFollow, "follow/set"))
        self._status = Lazy(lambda: node.create_client(GetFollowStatus, "follow/status"))
        self._lock = threading.Lock()
        self._sub: Any = None
        self.greeter = Greeter()
        self.greeting_text = DEFAULT_GREETING
        self.greeted = 0

    async def status(self) -> FollowStatus:
        res: GetFollowStatusResponse = await call_port(
            self._status.get(), Empty(), self.timeout, _absent)
        return res.status

    async def set_follow(self, mode: Literal["legs", "uwb"], enable: bool) -> FollowStatus:
        """Turn following in ``mode`` on or off; a refusal (a goal runs) is a `Conflict`."""
        res: SetFollowResponse = await call_port(
            self._set.get(), SetFollowRequest(mode=mode, enable=enable), self.timeout, _absent)
        if not res.success:
            raise Conflict(res.message)
        return res.status

    @property
    def greeting(self) -> bool:
        return self._sub is not None

    async def set_greeting(self, on: bool, text: str | None) -> None:
        """Greet people who come near (``text``, when given, is the new phrase); nav must be
        running (its leg detector finds them)."""
        if on:
            await self.status()  # Unavailable without nav
        with self._lock:
            if text is not None:
                self.greeting_text = text
            if on and self._sub is None:
                self.greeter = Greeter()
                self._sub = self.node.create_subscription(
                    PersonDetections, "people/detections", self.on_people)
            elif not on and self._sub is not None:
                sub, self._sub = self._sub, None
                self.node.destroy(sub)

    def on_people(self, msg: PersonDetections) -> None:
        with self._lock:
            greet = self._sub is not None and self.greeter.update(
                [(p.x, p.y) for p in msg.people], self.now())
            text = self.greeting_text
        if greet:
            self.greeted += 1
            self.node.logger.info("greeting a person: %r", text)
            self.speak(text)
