"""Action introspection over real Zenoh (ROS 2 Kilted's ``configure_introspection`` on an
action server): the requests and responses of its send_goal, cancel_goal and get_result
services on ``<action>/_action/<service>/_service_event``, with the contents or without,
and nothing while OFF."""

from __future__ import annotations

import threading
import time
from typing import Any

from zenros.action import ActionClient
from zenros.action.introspection import action_service_types
from zenros.action.types import uuid_msg
from zenros.action.wire import wire_types
from zenros.codec import codec_for
from zenros.msgs.example_interfaces import Fibonacci, FibonacciGoal, FibonacciResult
from zenros.msgs.service_msgs import ServiceEventInfo as Info
from zenros.service_events import ServiceIntrospectionState as State
from zenros.service_events import event_type_of
from zenros.testing import Collector, wait_for


def test_goals_cancels_and_results_are_seen_as_service_events(make_node: Any) -> None:
    release = threading.Event()

    def execute(handle: Any) -> FibonacciResult:
        if handle.request.order < 0:  # the goal a cancel ends
            while not handle.is_cancel_requested:
                time.sleep(0.01)
            handle.canceled()
            return FibonacciResult()
        release.wait(10)
        handle.succeed()
        return FibonacciResult(sequence=[0, 1, 1])

    server_node = make_node("fib_server", 0)
    server = server_node.create_action_server(Fibonacci, "/fib", execute, policy="parallel")
    server.configure_introspection(server_node.get_clock(), None, State.CONTENTS)
    watcher = make_node("watcher", 1)
    services = action_service_types(Fibonacci)
    got = {part: Collector[Any]() for part in services}
    for part, srv in services.items():
        watcher.create_subscription(event_type_of(srv), f"/fib/_action/{part}/_service_event",
                                    got[part])
    for part in services:
        events = getattr(server.events, part)
        assert events.wait_for_subscribers(1, 10)
    client_node = make_node("fib_client", 1)
    client = ActionClient(client_node, Fibonacci, "/fib")
    assert client.wait_for_server(10)

    handle = client.send_goal_async(FibonacciGoal(order=3))
    assert got["send_goal"].wait(2, 10), got["send_goal"].items
    request, response = sorted(got["send_goal"].items, key=lambda e: e.info.event_type)
    assert request.info.event_type == Info.REQUEST_RECEIVED
    assert request.request[0].goal == FibonacciGoal(order=3)
    assert response.info.event_type == Info.RESPONSE_SENT and response.response[0].accepted
    assert request.info.sequence_number == response.info.sequence_number
    release.set()
    assert handle.result(10).result.sequence == [0, 1, 1]
    # a result asked for apart from the goal (as rclpy's get_result_async does)
    # a result asked for on its own (as rclpy's get_result_async does; zenros's client has it
    # ride on the goal's query)
    client_ctx = client_node.context
    ask = codec_for(wire_types(Fibonacci).GetResultRequest).encode(
        wire_types(Fibonacci).GetResultRequest(goal_id=uuid_msg(handle.goal_id)))
    replies = list(client_ctx.session.get(client_ctx.keys.action("/fib", "get_result"),
                                          payload=ask, timeout=10))
    assert replies and replies[0].ok is not None
    assert got["get_result"].wait(2, 10)
    result_event = next(e for e in got["get_result"].items
                        if e.info.event_type == Info.RESPONSE_SENT)
    assert result_event.response[0].result.sequence == [0, 1, 1]

    cancelable = client.send_goal_async(FibonacciGoal(order=-1))
    assert wait_for(lambda: cancelable.accepted, 10)
    client.cancel_goal(cancelable.goal_id)
    assert got["cancel_goal"].wait(2, 10), got["cancel_goal"].items
    cancel_response = next(e for e in got["cancel_goal"].items
                           if e.info.event_type == Info.RESPONSE_SENT)
    assert cancel_response.response[0].return_code == 0
    assert len(cancel_response.response[0].goals_canceling) == 1

    server.configure_introspection(server_node.get_clock(), None, State.OFF)
    assert wait_for(lambda: not server_node.graph.publishers(
        "/fib/_action/send_goal/_service_event"), 10)
    before = len(got["send_goal"].items)
    assert client.send_goal_async(FibonacciGoal(order=1)).result(10).result.sequence
    assert len(got["send_goal"].items) == before  # events go out before the result does
