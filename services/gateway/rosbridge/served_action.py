"""`ServedAction`: a zenros action server whose goals a rosbridge client executes
(``advertise_action``), as the reference's advertised action handler does it.

Each goal goes to the client as ``send_action_goal`` with id ``action_goal:<name>:<n>``; the
client's ``action_feedback`` frames become feedback, its ``action_result`` ends the goal
(``status`` 4 succeeded, 5 canceled, anything else aborted; ``result: false`` aborts). A cancel
request from a zenros client reaches it as ``cancel_action_goal`` with the goal's id.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import itertools
from collections.abc import Callable
from typing import Any

from zenros.action import GoalStatus
from zenros.message import ActionType, Message

from .convert import long_type, message_from_json, to_json
from .frames import OpError

__all__ = ["ServedAction"]

Send = Callable[[dict[str, Any]], None]
CANCEL_MARK_WAIT = 2.0
"""Seconds a client's "canceled" result waits for the server to mark its goal canceling."""


class ServedAction:
    """The goals of one client-served action, by their rosbridge ids.

    Args:
        name: the action name.
        action_type: its type.
        send: queues a frame to the client (thread-safe: it hops onto the bridge's loop).
    """

    def __init__(self, name: str, action_type: ActionType[Message, Message, Message],
                 send: Send) -> None:
        self.name = name
        self.action_type = action_type
        self._send = send
        self._ids = itertools.count(1)
        self.goals: dict[str, tuple[concurrent.futures.Future[tuple[int, Message]], Any]] = {}
        self._cancels: set[str] = set()  # goals whose cancel the client was sent
        self.server: Any = None

    async def execute(self, handle: Any) -> Message:
        """The action server's execute callback (on the node's event loop)."""
        gid = f"action_goal:{self.name}:{next(self._ids)}"
        fut: concurrent.futures.Future[tuple[int, Message]] = concurrent.futures.Future()
        self.goals[gid] = (fut, handle)
        self._send({"op": "send_action_goal", "id": gid, "action": self.name,
                    "action_type": long_type(self.action_type.name, "action"),
                    "args": to_json(handle.request), "feedback": True})
        try:
            status, result = await asyncio.wrap_future(fut)
        except (OpError, RuntimeError):
            handle.abort()
            return self.action_type.Result()
        finally:
            self.goals.pop(gid, None)
            forwarded = gid in self._cancels
            self._cancels.discard(gid)
        if status == GoalStatus.SUCCEEDED:
            handle.succeed()
        elif status == GoalStatus.CANCELED and (handle.is_cancel_requested or forwarded and (
                await asyncio.to_thread(handle.wait_for_cancel, CANCEL_MARK_WAIT))):
            # A client may answer the cancel_action_goal we forwarded before the server has
            # marked the goal canceling (the cancel callback that forwards it runs first).
            handle.canceled()
        else:
            handle.abort()
        return result

    def on_cancel(self, handle: Any) -> bool:
        """The action server's cancel callback: tell the client; it decides how the goal ends."""
        for gid, (_, h) in list(self.goals.items()):
            if h is handle:
                self._cancels.add(gid)
                self._send({"op": "cancel_action_goal", "id": gid, "action": self.name})
        return True

    def _goal(self, gid: Any) -> tuple[concurrent.futures.Future[tuple[int, Message]], Any]:
        entry = self.goals.get(gid) if isinstance(gid, str) else None
        if entry is None:
            raise OpError(f"no goal of {self.name} in progress with id {gid!r}")
        return entry

    def feedback(self, gid: Any, values: Any) -> None:
        """The client's ``action_feedback`` for goal ``gid``."""
        _, handle = self._goal(gid)
        handle.publish_feedback(message_from_json(values, self.action_type.Feedback))

    def result(self, gid: Any, values: Any, status: Any, ok: bool) -> None:
        """The client's ``action_result`` for goal ``gid``."""
        fut, _ = self._goal(gid)
        if fut.done():
            return
        if not ok:
            fut.set_exception(OpError(f"the client aborted goal {gid}"))
            return
        if isinstance(status, bool) or not isinstance(status, int):
            raise OpError(f"Expected 'status' to be an int, got {status!r}")
        fut.set_result((status, message_from_json(values, self.action_type.Result)))

    def close(self) -> None:
        """Abort the goals still running (the client unadvertised or left)."""
        for fut, _ in list(self.goals.values()):
            if not fut.done():
                fut.set_exception(RuntimeError(f"action {self.name} was unadvertised"))
