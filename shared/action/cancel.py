"""Cancel requests: ask an action server to cancel one goal, all goals, or all before a stamp."""

from __future__ import annotations

import threading
import uuid

import zenoh

from ..codec import codec_for
from ..errors import ActionError, ActionServerUnavailableError, ZenrosTimeout
from ..msgs.builtin_interfaces import Time
from ..reach import Reach
from .transport import encoding_for, parse_error, query_once
from .types import CancelGoalRequest, CancelGoalResponse, GoalInfo, uuid_from_msg, uuid_msg

__all__ = ["request_cancel", "send_cancel"]

_REQ = codec_for(CancelGoalRequest)
_RES = codec_for(CancelGoalResponse)
_ENC = encoding_for(CancelGoalRequest)


def request_cancel(session: zenoh.Session, key: str, action: str, goal_id: uuid.UUID,
                   stamp: Time, timeout: float,
                   destination: zenoh.Locality = zenoh.Locality.ANY,
                   reach: Reach | None = None) -> list[uuid.UUID]:
    """Send one ``action_msgs/CancelGoal`` request (ROS 2 semantics: a zero ``goal_id`` names
    every goal, a non-zero ``stamp`` adds every goal accepted at or before it) and return the
    goals now canceling. Blocks; call it from your own thread, not a Zenoh callback.

    Raises:
        ActionServerUnavailableError: no server answered.
        ZenrosTimeout: the server did not answer within ``timeout`` seconds.
        ActionError: the server refused the request.
    """
    req = CancelGoalRequest(goal_info=GoalInfo(goal_id=uuid_msg(goal_id), stamp=stamp))
    res = send_cancel(session, key, action, req, timeout, destination, reach)
    return [uuid_from_msg(g.goal_id) for g in res.goals_canceling]


def send_cancel(session: zenoh.Session, key: str, action: str, req: CancelGoalRequest,
                timeout: float, destination: zenoh.Locality = zenoh.Locality.ANY,
                reach: Reach | None = None) -> CancelGoalResponse:
    """Send ``req`` to the action's cancel service and return the server's whole answer
    (``return_code`` and ``goals_canceling``); raises as `request_cancel`. With ``reach``,
    a request no server answered is sent again while the graph lists one."""
    data = _REQ.encode(req)

    def ask(left: float) -> zenoh.Reply | None:
        done = threading.Event()
        replies: list[zenoh.Reply | None] = []

        def on_reply(reply: zenoh.Reply | None) -> None:
            replies.append(reply)
            done.set()

        query_once(session, key, data, _ENC, left, on_reply, destination)
        if not done.wait(left + 1.0):
            raise ZenrosTimeout(f"action {action} did not answer cancel within {timeout:g} s")
        return replies[0]

    reply = ask(timeout) if reach is None else reach.ask(ask)
    if reply is None:
        raise ActionServerUnavailableError(f"no action server answered cancel on {action}")
    if reply.ok is None:
        assert reply.err is not None
        kind, message = parse_error(reply.err.payload.to_bytes())
        if kind == "Timeout":
            raise ZenrosTimeout(f"action {action} did not answer cancel within {timeout:g} s")
        raise ActionError(f"action {action}: cancel failed: {message}")
    res: CancelGoalResponse = _RES.decode(reply.ok.payload.to_bytes())
    return res
