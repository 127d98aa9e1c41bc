"""test_msgs: the Fibonacci action of ROS 2's test_msgs package (the interface the ROS 2
wheels ship, which rclpy tests and the ROS 2 bridges' tests use). Not imported by
`zenros.msgs` (its short name would make ``Fibonacci`` ambiguous with example_interfaces's):
`zenros.registry` imports it the first time a name names its package
(``test_msgs/action/Fibonacci``), in every tool and bridge."""

from __future__ import annotations

import msgspec

from ..message import Message, define_action


class FibonacciGoal(Message):
    __msgtype__ = "test_msgs/FibonacciGoal"
    order: int = 0


class FibonacciResult(Message):
    __msgtype__ = "test_msgs/FibonacciResult"
    sequence: list[int] = msgspec.field(default_factory=list)


class FibonacciFeedback(Message):
    __msgtype__ = "test_msgs/FibonacciFeedback"
    sequence: list[int] = msgspec.field(default_factory=list)


Fibonacci = define_action("test_msgs/Fibonacci", FibonacciGoal, FibonacciResult, FibonacciFeedback)
