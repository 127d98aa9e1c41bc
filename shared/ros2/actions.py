"""An action's parts under their ROS 2 names: the zenros wire classes of send_goal,
cancel_goal and get_result with their MessagePack/JSON codecs, the CDR codecs of the same
classes under rosidl's names, and the feedback and status codecs, shared by the bridges that
carry actions between zenros and ROS 2 (rmw_zenoh, DDS)."""

from __future__ import annotations

from typing import Any

import zenoh

from ..action.transport import encoding_for
from ..action.types import CancelGoalRequest, CancelGoalResponse, GoalStatusArray
from ..action.wire import wire_types
from ..codec import Codec, codec_for
from ..message import ActionType, Message
from .cdr import CdrCodec, cdr_codec

__all__ = ["SERVICES", "ActionPart", "Topics", "action_parts", "ros_action_name"]

SERVICES = ("send_goal", "cancel_goal", "get_result")
"""The three services rcl_action makes of an action (under ``<name>/_action/``)."""


class ActionPart:
    """One request/response pair: the zenros codecs and the CDR codecs of the same classes."""

    def __init__(self, req: type[Message], res: type[Message], ros_req: str, ros_res: str) -> None:
        self.req_native: Codec[Any] = codec_for(req)
        self.res_native: Codec[Any] = codec_for(res)
        self.req_cdr: CdrCodec[Any] = CdrCodec(req, ros_req)
        self.res_cdr: CdrCodec[Any] = CdrCodec(res, ros_res)
        self.req_enc: zenoh.Encoding = encoding_for(req)
        self.res_enc: zenoh.Encoding = encoding_for(res)


class Topics:
    """The feedback and status topics' codecs, zenros and CDR, and the feedback encoding."""

    def __init__(self, action: ActionType) -> None:
        w = wire_types(action)
        self.fb_native: Codec[Any] = codec_for(w.FeedbackMessage)
        self.fb_cdr: CdrCodec[Any] = CdrCodec(w.FeedbackMessage,
                                              f"{ros_action_name(action)}_FeedbackMessage")
        self.fb_enc: zenoh.Encoding = encoding_for(w.FeedbackMessage)
        self.st_native: Codec[Any] = codec_for(GoalStatusArray)
        self.st_cdr: CdrCodec[Any] = cdr_codec(GoalStatusArray)


def ros_action_name(action: ActionType) -> str:
    """``test_msgs/Fibonacci`` -> ``test_msgs/action/Fibonacci``."""
    pkg, _, short = action.name.partition("/")
    return f"{pkg}/action/{short}"


def action_parts(action: ActionType) -> dict[str, ActionPart]:
    """The codecs of an action's three services, by part name."""
    w = wire_types(action)
    ros = ros_action_name(action)
    return {
        "send_goal": ActionPart(w.SendGoalRequest, w.SendGoalResponse,
                                f"{ros}_SendGoal_Request", f"{ros}_SendGoal_Response"),
        "cancel_goal": ActionPart(CancelGoalRequest, CancelGoalResponse,
                                  "action_msgs/srv/CancelGoal_Request",
                                  "action_msgs/srv/CancelGoal_Response"),
        "get_result": ActionPart(w.GetResultRequest, w.GetResultResponse,
                                 f"{ros}_GetResult_Request", f"{ros}_GetResult_Response"),
    }
