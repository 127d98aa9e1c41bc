"""example_interfaces: AddTwoInts (service) and Fibonacci (action), as in the ROS tutorials."""

from __future__ import annotations

import msgspec

from ..message import Message, define_action, define_service


class AddTwoIntsRequest(Message):
    __msgtype__ = "example_interfaces/AddTwoIntsRequest"
    a: int = 0
    b: int = 0


class AddTwoIntsResponse(Message):
    __msgtype__ = "example_interfaces/AddTwoIntsResponse"
    sum: int = 0


AddTwoInts = define_service("example_interfaces/AddTwoInts", AddTwoIntsRequest, AddTwoIntsResponse)


class FibonacciGoal(Message):
    __msgtype__ = "example_interfaces/FibonacciGoal"
    order: int = 0


class FibonacciResult(Message):
    __msgtype__ = "example_interfaces/FibonacciResult"
    sequence: list[int] = msgspec.field(default_factory=list)


class FibonacciFeedback(Message):
    __msgtype__ = "example_interfaces/FibonacciFeedback"
    sequence: list[int] = msgspec.field(default_factory=list)


Fibonacci = define_action(
    "example_interfaces/Fibonacci", FibonacciGoal, FibonacciResult, FibonacciFeedback
)
