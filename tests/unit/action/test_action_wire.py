"""Action wire messages (strict, with paths in errors) and the server's goal table (no Zenoh)."""

from __future__ import annotations

import uuid
from typing import Any

import pytest
from zenros.action.goal_handle import ServerGoalHandle
from zenros.action.goals import GoalTable
from zenros.action.types import (
    UUID,
    CancelGoal,
    GoalStatus,
    GoalStatusArray,
    uuid_from_msg,
    uuid_msg,
)
from zenros.action.wire import wire_types
from zenros.codec import codec_for
from zenros.errors import DecodeError
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.example_interfaces import Fibonacci, FibonacciGoal, FibonacciResult
from zenros.registry import lookup_service, lookup_type


def test_wire_types_are_cached_and_registered_under_ros2_names() -> None:
    w = wire_types(Fibonacci)
    assert wire_types(Fibonacci) is w
    for cls, name in [
        (w.SendGoalRequest, "example_interfaces/Fibonacci_SendGoal_Request"),
        (w.SendGoalResponse, "example_interfaces/Fibonacci_SendGoal_Response"),
        (w.GetResultRequest, "example_interfaces/Fibonacci_GetResult_Request"),
        (w.GetResultResponse, "example_interfaces/Fibonacci_GetResult_Response"),
        (w.FeedbackMessage, "example_interfaces/Fibonacci_FeedbackMessage"),
    ]:
        assert cls.__msgtype__ == name
        assert lookup_type(name) is cls
        assert lookup_type(name.replace("/", "/action/", 1)) is cls
    assert lookup_service("action_msgs/srv/CancelGoal") is CancelGoal
    assert lookup_type("action_msgs/GoalStatusArray") is GoalStatusArray


def test_send_goal_request_round_trips_in_ros_layout() -> None:
    w = wire_types(Fibonacci)
    gid = uuid.uuid4()
    codec = codec_for(w.SendGoalRequest)
    data = codec.encode(w.SendGoalRequest(goal_id=uuid_msg(gid), goal=FibonacciGoal(order=5)))
    assert data == (b'{"goal_id":{"uuid":[' + ",".join(str(b) for b in gid.bytes).encode()
                    + b']},"goal":{"order":5}}')
    back = codec.decode(data)
    assert uuid_from_msg(back.goal_id) == gid and back.goal == FibonacciGoal(order=5)


@pytest.mark.parametrize(
    ("payload", "needle"),
    [
        (b'{"goal":{"order":1}}', "missing required field `goal_id`"),
        (b'{"goal_id":{"uuid":[1,2]},"goal":{}}', "length >= 16"),
        (b'{"goal_id":{"uuid":[' + b"300," * 15 + b'1]}}', "<= 255 - at `$.goal_id.uuid[0]`"),
        (b'{"goal_id":{"uuid":[' + b"1," * 15 + b'1]},"goal":{"order":"x"}}',
         "Expected `int`, got `str` - at `$.goal.order`"),
        (b"not json", "malformed"),
    ],
)
def test_bad_send_goal_requests_fail_with_a_path(payload: bytes, needle: str) -> None:
    codec = codec_for(wire_types(Fibonacci).SendGoalRequest)
    with pytest.raises(DecodeError) as err:
        codec.decode(payload)
    assert "expected example_interfaces/Fibonacci_SendGoal_Request" in str(err.value)
    assert needle in str(err.value)


def test_result_response_carries_the_typed_result() -> None:
    w = wire_types(Fibonacci)
    codec = codec_for(w.GetResultResponse)
    res = codec.decode(b'{"status":4,"result":{"sequence":[0,1,1]}}')
    assert res.status == 4 and res.result == FibonacciResult(sequence=[0, 1, 1])
    assert codec.decode(b"{}").result == FibonacciResult()


def test_zero_uuid_is_the_default() -> None:
    assert uuid_from_msg(UUID()) == uuid.UUID(int=0)


# ------------------------------------------------------------------ goal table


def goal(n: int, status: GoalStatus = GoalStatus.EXECUTING, sec: int = 0) -> Any:
    h: ServerGoalHandle[Any] = ServerGoalHandle(None, uuid.UUID(int=n), None)
    h._status = status
    h.stamp = Time(sec=sec)
    return h


def test_results_expire_oldest_first() -> None:
    t = GoalTable(result_timeout=10.0, status_history=16)
    a, b = goal(1), goal(2)
    for h in (a, b):
        assert t.add_pending(h)
        t.activate(h)
    assert not t.add_pending(goal(1))  # duplicate id
    t.retire(a, now=100.0)
    t.retire(b, now=105.0)
    assert t.next_expiry() == 110.0
    assert t.expire(109.9) == []
    assert t.expire(110.0) == [a]
    assert t.lookup(a.key) is None and t.lookup(b.key) is b
    assert t.expire(200.0) == [b] and len(t) == 0 and t.next_expiry() is None


def test_status_list_is_active_goals_then_recent_history() -> None:
    t = GoalTable(result_timeout=10.0, status_history=2)
    hs = [goal(i) for i in range(1, 6)]
    for h in hs:
        t.add_pending(h)
        t.activate(h)
    for h in hs[:3]:
        t.retire(h, now=1.0)
    assert t.status_list() == [hs[3], hs[4], hs[1], hs[2]]


def test_cancel_targets_follow_ros2_rules() -> None:
    t = GoalTable(result_timeout=10.0, status_history=2)
    hs = [goal(i, sec=i) for i in range(1, 5)]
    for h in hs:
        t.add_pending(h)
        t.activate(h)
    hs[3]._status = GoalStatus.SUCCEEDED  # ended, result not yet set: not cancelable
    assert list(t.cancel_targets(hs[1].key, 0)) == [hs[1]]
    assert list(t.cancel_targets(None, 0)) == hs[:3]
    assert list(t.cancel_targets(None, 2_000_000_000)) == hs[:2]
    assert list(t.cancel_targets(hs[2].key, 1_000_000_000)) == [hs[0], hs[2]]
    assert t.terminal_or_unknown(hs[3].key) is GoalStatus.SUCCEEDED
    assert t.terminal_or_unknown(b"x" * 16) is GoalStatus.UNKNOWN


def test_goal_table_refuses_negative_settings() -> None:
    with pytest.raises(ValueError, match="result_timeout must be >= 0 s"):
        GoalTable(-1.0, 1)
    with pytest.raises(ValueError, match="status_history must be >= 0"):
        GoalTable(1.0, -1)
