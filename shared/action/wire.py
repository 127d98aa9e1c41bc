"""The per-action wire messages (``<pkg>/<Name>_SendGoal_Request`` ...), generated once per type.

ROS 2 generates five messages per action that wrap the goal, result and feedback with a goal
id and a status. zenros builds them at run time as typed msgspec Structs, so decoding stays
strict and its errors name the path (``at $.goal.order``), and registers them under ROS 2's
names so tools can decode them by the schema in the sample encoding.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import Any

import msgspec

from ..codec import Codec, codec_for
from ..message import ActionType, Message
from ..msgs.builtin_interfaces import Time
from .types import UUID

__all__ = [
    "ActionWire",
    "FeedbackMessage",
    "GetResultRequest",
    "GetResultResponse",
    "SendGoalRequest",
    "SendGoalResponse",
    "wire_types",
]


class SendGoalRequest(Message, kw_only=True):
    """Base of ``<Name>_SendGoal_Request``: a client-chosen goal id and the goal."""

    goal_id: UUID
    goal: Any = None


class SendGoalResponse(Message, kw_only=True):
    """Base of ``<Name>_SendGoal_Response``: accepted or not, the acceptance stamp, and (a
    zenros addition, empty in ROS) why a goal was rejected."""

    accepted: bool = False
    stamp: Time = msgspec.field(default_factory=Time)
    reason: str = ""


class GetResultRequest(Message, kw_only=True):
    """Base of ``<Name>_GetResult_Request``: which goal's result."""

    goal_id: UUID


class GetResultResponse(Message, kw_only=True):
    """Base of ``<Name>_GetResult_Response``: the terminal status (4-6) and the result."""

    status: int = 0
    result: Any = None


class FeedbackMessage(Message, kw_only=True):
    """Base of ``<Name>_FeedbackMessage``: feedback for one goal."""

    goal_id: UUID
    feedback: Any = None


@dataclass(frozen=True)
class ActionWire:
    """The five wire message classes of one action type."""

    SendGoalRequest: type[SendGoalRequest]
    SendGoalResponse: type[SendGoalResponse]
    GetResultRequest: type[GetResultRequest]
    GetResultResponse: type[GetResultResponse]
    FeedbackMessage: type[FeedbackMessage]

    def codecs(self) -> tuple[Codec[Any], Codec[Any], Codec[Any], Codec[Any], Codec[Any]]:
        """The codecs of the five classes, in field order (cached per class)."""
        return (codec_for(self.SendGoalRequest), codec_for(self.SendGoalResponse),
                codec_for(self.GetResultRequest), codec_for(self.GetResultResponse),
                codec_for(self.FeedbackMessage))  # fmt: skip


def _derive(base: type[Message], type_name: str, field: str | None = None,
            field_type: type[Message] | None = None) -> Any:
    fields: list[Any] = []
    if field is not None and field_type is not None:
        fields.append((field, field_type, msgspec.field(default_factory=field_type)))
    short = type_name.rsplit("/", 1)[-1]
    return msgspec.defstruct(short, fields, bases=(base,), kw_only=True,
                             namespace={"__msgtype__": type_name, "__module__": __name__})


@cache
def wire_types(action: ActionType) -> ActionWire:
    """The wire messages of ``action``, built and registered on first use."""
    n = action.name
    return ActionWire(
        SendGoalRequest=_derive(SendGoalRequest, f"{n}_SendGoal_Request", "goal", action.Goal),
        SendGoalResponse=_derive(SendGoalResponse, f"{n}_SendGoal_Response"),
        GetResultRequest=_derive(GetResultRequest, f"{n}_GetResult_Request"),
        GetResultResponse=_derive(GetResultResponse, f"{n}_GetResult_Response", "result",
                                  action.Result),
        FeedbackMessage=_derive(FeedbackMessage, f"{n}_FeedbackMessage", "feedback",
                                action.Feedback),
    )
