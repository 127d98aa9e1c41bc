"""action_tutorials_interfaces: the Fibonacci action of the ROS 2 action tutorials (its
feedback is ``partial_sequence``), as roslibjs's ROS 2 examples name it. Not imported by
`zenros.msgs` (its short name would make ``Fibonacci`` ambiguous with example_interfaces's);
`zenros.registry` imports it the first time a name names its package, and the rosbridge
server imports it (docs/rosbridge.md, "Tutorial action types")."""

from __future__ import annotations

import msgspec

from ..message import Message, define_action


class FibonacciGoal(Message):
    __msgtype__ = "action_tutorials_interfaces/FibonacciGoal"
    order: int = 0


class FibonacciResult(Message):
    __msgtype__ = "action_tutorials_interfaces/FibonacciResult"
    sequence: list[int] = msgspec.field(default_factory=list)


class FibonacciFeedback(Message):
    __msgtype__ = "action_tutorials_interfaces/FibonacciFeedback"
    partial_sequence: list[int] = msgspec.field(default_factory=list)


Fibonacci = define_action("action_tutorials_interfaces/Fibonacci", FibonacciGoal,
                          FibonacciResult, FibonacciFeedback)
