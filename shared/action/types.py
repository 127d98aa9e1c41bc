"""Action vocabulary: goal states, callback answers, and the fixed `action_msgs` wire messages."""

from __future__ import annotations

import uuid
from enum import Enum, IntEnum
from typing import Annotated

import msgspec

from ..message import Message, define_service
from ..msgs.builtin_interfaces import Time

__all__ = [
    "UUID",
    "ZERO_UUID",
    "CancelCode",
    "CancelGoal",
    "CancelGoalRequest",
    "CancelGoalResponse",
    "CancelResponse",
    "GoalInfo",
    "GoalResponse",
    "GoalStatus",
    "GoalStatusArray",
    "GoalStatusMsg",
    "uuid_from_msg",
    "uuid_msg",
]


class GoalStatus(IntEnum):
    """A goal's state. 0-6 are ROS 2's ``action_msgs/GoalStatus`` values and travel on the
    wire; REJECTED and LOST exist only on the client side (as in ROS 1 actionlib): the server
    refused the goal at send time, or the server went away before the goal ended."""

    UNKNOWN = 0
    ACCEPTED = 1
    EXECUTING = 2
    CANCELING = 3
    SUCCEEDED = 4
    CANCELED = 5
    ABORTED = 6
    REJECTED = 7
    LOST = 8

    @property
    def terminal(self) -> bool:
        """True for a state a goal never leaves."""
        return self >= GoalStatus.SUCCEEDED

    @property
    def active(self) -> bool:
        """True while the goal is accepted, executing or canceling."""
        return GoalStatus.ACCEPTED <= self <= GoalStatus.CANCELING


class GoalResponse(Enum):
    """What a goal callback answers (rclpy's names)."""

    REJECT = 1
    ACCEPT = 2


class CancelResponse(Enum):
    """What a cancel callback answers (rclpy's names)."""

    REJECT = 1
    ACCEPT = 2


class CancelCode(IntEnum):
    """``action_msgs/CancelGoal`` return codes."""

    ERROR_NONE = 0
    ERROR_REJECTED = 1
    ERROR_UNKNOWN_GOAL_ID = 2
    ERROR_GOAL_TERMINATED = 3


_Byte = Annotated[int, msgspec.Meta(ge=0, le=255)]
_Bytes16 = Annotated[list[_Byte], msgspec.Meta(min_length=16, max_length=16)]


class UUID(Message, kw_only=True):
    """``unique_identifier_msgs/UUID``: 16 bytes, written as a list of numbers (ROS layout)."""

    __msgtype__ = "unique_identifier_msgs/UUID"
    uuid: _Bytes16 = msgspec.field(default_factory=lambda: [0] * 16)


ZERO_UUID = uuid.UUID(int=0)


def uuid_msg(value: uuid.UUID) -> UUID:
    """The wire form of a Python UUID."""
    return UUID(uuid=list(value.bytes))


def uuid_from_msg(msg: UUID) -> uuid.UUID:
    """The Python UUID of a wire UUID."""
    return uuid.UUID(bytes=bytes(msg.uuid))


class GoalInfo(Message, kw_only=True):
    """``action_msgs/GoalInfo``: a goal's id and the time the server accepted it."""

    __msgtype__ = "action_msgs/GoalInfo"
    goal_id: UUID = msgspec.field(default_factory=UUID)
    stamp: Time = msgspec.field(default_factory=Time)


class GoalStatusMsg(Message, kw_only=True):
    """``action_msgs/GoalStatus``: one goal and its state (0-6, see `GoalStatus`)."""

    __msgtype__ = "action_msgs/GoalStatus"
    goal_info: GoalInfo = msgspec.field(default_factory=GoalInfo)
    status: Annotated[int, msgspec.Meta(ge=0, le=6)] = 0


class GoalStatusArray(Message, kw_only=True):
    """``action_msgs/GoalStatusArray``: what an action server publishes, latched, on ``status``."""

    __msgtype__ = "action_msgs/GoalStatusArray"
    status_list: list[GoalStatusMsg] = msgspec.field(default_factory=list)


class CancelGoalRequest(Message, kw_only=True):
    """``action_msgs/CancelGoal`` request. A zero id with a zero stamp cancels every goal; a
    zero id with a stamp, every goal accepted at or before it; an id, that goal (and, with a
    stamp, also every goal accepted at or before the stamp)."""

    __msgtype__ = "action_msgs/CancelGoal_Request"
    goal_info: GoalInfo = msgspec.field(default_factory=GoalInfo)


class CancelGoalResponse(Message, kw_only=True):
    """``action_msgs/CancelGoal`` response: a `CancelCode` and the goals now canceling."""

    __msgtype__ = "action_msgs/CancelGoal_Response"
    return_code: int = 0
    goals_canceling: list[GoalInfo] = msgspec.field(default_factory=list)


CancelGoal = define_service("action_msgs/CancelGoal", CancelGoalRequest, CancelGoalResponse)
