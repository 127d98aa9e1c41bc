"""`ServedAction` (a zenros action whose goals a rosbridge client executes): how the client's
``action_result`` status ends the goal, without a network."""

from __future__ import annotations

import asyncio
import threading
import time
from typing import Any

from zenros.action import GoalStatus
from zenros.msgs.example_interfaces import Fibonacci, FibonacciGoal
from zenros.services.gateway.rosbridge.served_action import ServedAction


class Handle:
    """The goal handle `ServedAction.execute` drives: records how the goal ended."""

    def __init__(self) -> None:
        self.request = FibonacciGoal(order=3)
        self.is_cancel_requested = False
        self.ended: str | None = None

    def wait_for_cancel(self, timeout: float | None = None) -> bool:
        deadline = time.monotonic() + (timeout or 0.0)
        while not self.is_cancel_requested and time.monotonic() < deadline:
            time.sleep(0.001)
        return self.is_cancel_requested

    def succeed(self) -> None:
        self.ended = "succeeded"

    def canceled(self) -> None:
        self.ended = "canceled"

    def abort(self) -> None:
        self.ended = "aborted"


def _run(answer: Any, handle: Handle) -> str | None:
    """Execute one goal; ``answer(action, goal_frame)`` plays the client from a thread."""
    sent: list[dict[str, Any]] = []
    action = ServedAction("/fib", Fibonacci, sent.append)

    async def main() -> None:
        task = asyncio.ensure_future(action.execute(handle))
        while not sent:
            await asyncio.sleep(0.001)
        threading.Thread(target=answer, args=(action, sent[0])).start()
        await task

    asyncio.run(main())
    return handle.ended


def test_canceled_before_the_server_marks_the_goal_canceling_ends_canceled() -> None:
    """A fast client answers the forwarded ``cancel_action_goal`` before the server has marked
    the goal canceling (the cancel callback, which forwards it, runs first)."""
    handle = Handle()

    def client(action: ServedAction, goal: dict[str, Any]) -> None:
        action.on_cancel(handle)  # forwards cancel_action_goal; the mark comes later
        action.result(goal["id"], {"sequence": [0]}, int(GoalStatus.CANCELED), True)
        threading.Timer(0.05, setattr, (handle, "is_cancel_requested", True)).start()

    assert _run(client, handle) == "canceled"


def test_canceled_without_a_cancel_request_aborts() -> None:
    handle = Handle()

    def client(action: ServedAction, goal: dict[str, Any]) -> None:
        action.result(goal["id"], {"sequence": [0]}, int(GoalStatus.CANCELED), True)

    assert _run(client, handle) == "aborted"


def test_succeeded_and_any_other_status() -> None:
    for status, ended in ((GoalStatus.SUCCEEDED, "succeeded"), (GoalStatus.ABORTED, "aborted")):
        handle = Handle()

        def client(action: ServedAction, goal: dict[str, Any], s: int = int(status)) -> None:
            action.result(goal["id"], {"sequence": [0, 1]}, s, True)

        assert _run(client, handle) == ended
