"""Actions: long-running goals with feedback, cancellation and preemption (ROS actionlib).

A server answers three queryables (``send_goal``, ``cancel_goal``, ``get_result``) and
publishes two topics (``feedback``, and ``status``, latched) under
``<prefix>/action/<name>/``; see docs/actions.md.
"""

from .client import ActionClient
from .client_goal import ClientGoalHandle, GoalResult
from .goal_handle import ServerGoalHandle
from .policies import GoalPolicy
from .server import ActionServer
from .types import (
    CancelCode,
    CancelGoalRequest,
    CancelGoalResponse,
    CancelResponse,
    GoalInfo,
    GoalResponse,
    GoalStatus,
    GoalStatusArray,
    GoalStatusMsg,
)
from .wire import wire_types

__all__ = [
    "ActionClient",
    "ActionServer",
    "CancelCode",
    "CancelGoalRequest",
    "CancelGoalResponse",
    "CancelResponse",
    "ClientGoalHandle",
    "GoalInfo",
    "GoalPolicy",
    "GoalResponse",
    "GoalResult",
    "GoalStatus",
    "GoalStatusArray",
    "GoalStatusMsg",
    "ServerGoalHandle",
    "wire_types",
]
