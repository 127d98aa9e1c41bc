"""`ServerGoalHandle` owns its state: every change goes through `transition`, under its
server's lock, and tells the server (`GoalHost`)."""

from __future__ import annotations

import threading
import uuid
from typing import Any

import pytest
from zenros.action import GoalStatus, ServerGoalHandle
from zenros.action.states import GoalEvent
from zenros.errors import GoalStateError


class Host:
    """A `GoalHost` that records what the handle asks of it."""

    def __init__(self) -> None:
        self.lock = threading.RLock()
        self.changes: list[GoalStatus] = []
        self.sent: list[bytes] = []
        self.handle: ServerGoalHandle[Any, Any] | None = None

    def goal_changed(self) -> None:
        assert self.lock._is_owned()  # type: ignore[attr-defined]  # under the lock
        assert self.handle is not None
        self.changes.append(self.handle.status)

    def encode_feedback(self, handle: ServerGoalHandle[Any, Any], feedback: Any) -> bytes:
        return str(feedback).encode()

    def put_feedback(self, handle: ServerGoalHandle[Any, Any], data: bytes) -> None:
        assert self.lock._is_owned()  # type: ignore[attr-defined]
        self.sent.append(data)


def _handle() -> tuple[Host, ServerGoalHandle[Any, Any]]:
    host = Host()
    h: ServerGoalHandle[Any, Any] = ServerGoalHandle(host, uuid.uuid4(), "goal")
    host.handle = h
    return host, h


def test_the_handle_moves_itself_and_tells_its_server() -> None:
    host, h = _handle()
    assert h.status is GoalStatus.UNKNOWN
    assert h.transition(GoalEvent.ACCEPT) is GoalStatus.ACCEPTED
    h.transition(GoalEvent.EXECUTE)
    h.publish_feedback(1)
    h.succeed()
    assert host.changes == [GoalStatus.ACCEPTED, GoalStatus.EXECUTING, GoalStatus.SUCCEEDED]
    assert host.sent == [b"1"] and not h.is_active


def test_a_cancel_request_raises_the_flag_and_wakes_the_waiter() -> None:
    _, h = _handle()
    h.transition(GoalEvent.ACCEPT)
    h.transition(GoalEvent.EXECUTE)
    woke: list[bool] = []
    waiter = threading.Thread(target=lambda: woke.append(h.wait_for_cancel(10)))
    waiter.start()
    assert not h.is_cancel_requested
    h.transition(GoalEvent.CANCEL_GOAL)
    waiter.join(10)
    assert woke == [True] and h.is_cancel_requested and h.status is GoalStatus.CANCELING
    h.canceled()
    assert h.status is GoalStatus.CANCELED


def test_invalid_moves_name_the_valid_ones_and_change_nothing() -> None:
    host, h = _handle()
    h.transition(GoalEvent.ACCEPT)
    h.transition(GoalEvent.EXECUTE)
    with pytest.raises(GoalStateError, match=r"cannot canceled while EXECUTING \(cancel was "
                                             r"not requested\); valid now: cancel_goal, "
                                             r"succeed, abort"):
        h.canceled()
    h.abort()
    with pytest.raises(GoalStateError, match="valid now: none"):
        h.succeed()
    with pytest.raises(GoalStateError, match="it is ABORTED"):
        h.publish_feedback(2)
    assert h.status is GoalStatus.ABORTED and host.sent == []
    assert host.changes == [GoalStatus.ACCEPTED, GoalStatus.EXECUTING, GoalStatus.ABORTED]
