"""`Outcome`: how a robot call or a task action ended (``complete``, ``fail``, ``error``,
``preempted``) and why."""

from __future__ import annotations

from typing import Literal, NamedTuple

__all__ = ["Outcome", "OutcomeName"]

OutcomeName = Literal["complete", "fail", "error", "preempted"]


class Outcome(NamedTuple):
    name: OutcomeName
    reason: str = ""
