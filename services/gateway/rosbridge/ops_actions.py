"""`ActionOps`: rosbridge action goals (``send_action_goal``, ``cancel_action_goal``) to
zenros actions, with ``action_feedback`` and ``action_result`` back."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

from zenros.errors import ZenrosError
from zenros.message import Message
from zenros.registry import lookup_action

from .bridge import BridgeError
from .capability import Capability, Session
from .convert import message_from_json, to_json
from .equivalents import convert, served_type
from .frames import (
    ActionFeedback,
    ActionResult,
    AdvertiseAction,
    CancelActionGoal,
    OpError,
    SendActionGoal,
    UnadvertiseAction,
    frame_int,
    frame_name,
    frame_type,
    legacy_id,
)
from .served_action import ServedAction

__all__ = ["ActionOps"]


class ActionOps(Capability):
    """The goals one client sent, by interaction id, and the actions it serves
    (`ServedAction`), by name."""

    ops = {SendActionGoal: "op_send_action_goal", CancelActionGoal: "op_cancel_action_goal",
           AdvertiseAction: "op_advertise_action", UnadvertiseAction: "op_unadvertise_action",
           ActionFeedback: "op_action_feedback", ActionResult: "op_action_result"}

    def __init__(self, session: Session) -> None:
        super().__init__(session)
        self.goals: dict[Any, Any] = {}
        self.served_actions: dict[str, ServedAction] = {}

    def op_send_action_goal(self, frame: SendActionGoal) -> None:
        if not frame.action:
            raise OpError("Expected a key 'action' with a string in message")
        self.spawn(self._send_goal(frame.action, legacy_id(frame, "action"), frame))

    async def _send_goal(self, given: str, mid: Any, frame: SendActionGoal) -> None:
        def reply(values: Any, status: int, ok: bool) -> None:
            out: dict[str, Any] = {"op": "action_result", "action": given, "values": values,
                                   "status": status, "result": ok}
            if mid is not None:
                out["id"] = mid
            self.send(out, frame_int(frame, "fragment_size"))

        try:
            action = frame_name(frame, "action")
            action_type = frame_type(frame, "action_type", lookup_action)
            goal = message_from_json(frame.args or {}, action_type.Goal)
            served = served_type(action_type, self.bridge.node.graph.actions().get(action, []))
            client = self.bridge.action_client(served, action)
            on_feedback = (self._feedback_sender(given, mid, action_type.Feedback)
                           if frame.feedback else None)
            handle = client.send_goal_async(convert(goal, served.Goal), on_feedback)
            if mid is not None:
                self.goals[mid] = handle
            try:
                result = await handle.result_async()
            finally:
                if mid is not None:
                    self.goals.pop(mid, None)
        except (OpError, BridgeError, ZenrosError, ValueError, TypeError) as exc:
            self.report("error", f"send_action_goal {type(exc).__name__}: {exc}", mid)
            reply(str(exc), 0, False)
            return
        status = int(result.status) if result.status <= 6 else 0
        if result.reason and status == 0:
            reply(result.reason, 0, False)
            return
        reply(to_json(convert(result.result, action_type.Result)), status, True)

    def _feedback_sender(self, action: str, mid: Any,
                         feedback_type: type[Message]) -> Callable[[Any], None]:
        loop = self.bridge.loop

        def on_feedback(msg: Any) -> None:  # on the action client's feedback thread
            out: dict[str, Any] = {"op": "action_feedback", "action": action,
                                   "values": to_json(convert(msg.feedback, feedback_type))}
            if mid is not None:
                out["id"] = mid
            loop.call_soon_threadsafe(self.send, out)

        return on_feedback

    def op_cancel_action_goal(self, frame: CancelActionGoal) -> None:
        mid = legacy_id(frame, "action")
        handle = self.goals.get(mid)
        if handle is None:
            raise OpError(f"no goal in progress with id {mid!r}")
        self.spawn(asyncio.to_thread(handle.cancel))

    # ------------------------------------------------------------------ serving actions

    def op_advertise_action(self, frame: AdvertiseAction) -> None:
        action = frame_name(frame, "action")
        action_type = frame_type(frame, "type", lookup_action)
        old = self.served_actions.get(action)
        if old is not None:
            if old.action_type is action_type:
                return  # a replay after reconnect
            self.stop_served_action(action)
        loop = self.bridge.loop

        def send(out: dict[str, Any]) -> None:  # from the node's threads
            loop.call_soon_threadsafe(self.send, out)

        served = ServedAction(action, action_type, send)
        served.server = self.bridge.node.create_action_server(
            action_type, action, served.execute, cancel_callback=served.on_cancel,
            policy="parallel")
        self.served_actions[action] = served

    def op_unadvertise_action(self, frame: UnadvertiseAction) -> None:
        self.stop_served_action(frame_name(frame, "action"))

    def _served(self, frame: ActionFeedback | ActionResult) -> ServedAction:
        action = frame_name(frame, "action")
        served = self.served_actions.get(action)
        if served is None:
            raise OpError(f"Action {action} has not been advertised via rosbridge.")
        return served

    def op_action_feedback(self, frame: ActionFeedback) -> None:
        self._served(frame).feedback(frame.id, frame.values)

    def op_action_result(self, frame: ActionResult) -> None:
        self._served(frame).result(frame.id, frame.values, frame.status, frame.result)

    def stop_served_action(self, action: str) -> None:
        """Abort the action's running goals and close its server (off the loop: closing waits
        for the goals to end)."""
        served = self.served_actions.pop(action, None)
        if served is None:
            return
        served.close()
        self.bridge.loop.run_in_executor(None, served.server.close)

    def close(self) -> None:
        """Stop the actions this client serves; cancel its goals (a goal of a client that
        left is canceled, not orphaned)."""
        for action in list(self.served_actions):
            self.stop_served_action(action)
        loop = self.bridge.loop
        for handle in list(self.goals.values()):
            if not handle.done:
                loop.run_in_executor(None, handle.cancel)
        self.goals.clear()
