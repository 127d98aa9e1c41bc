"""Managed (lifecycle) nodes as ROS 2 has them, and a lifecycle manager (docs/lifecycle.md).

`LifecycleNode` runs rcl's state machine (`zenros.lifecycle.machine`) behind ROS 2's
services and topic names; `zenros.lifecycle.manager` brings a list of them up in order and
takes them down when one stops sending its bond heartbeat.
"""

from .machine import (
    InvalidTransitionError,
    LifecycleState,
    StateMachine,
    TransitionCallbackReturn,
)
from .node import LifecycleNode, LifecyclePublisher, ManagedEntity, SimpleManagedEntity

__all__ = [
    "InvalidTransitionError",
    "LifecycleNode",
    "LifecyclePublisher",
    "LifecycleState",
    "ManagedEntity",
    "SimpleManagedEntity",
    "StateMachine",
    "TransitionCallbackReturn",
]
