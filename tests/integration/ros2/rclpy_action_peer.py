"""An unmodified rclpy action server (or watcher) for the DDS bridge tests.

``python rclpy_action_peer.py NAME`` serves test_msgs/action/Fibonacci on NAME until killed. A goal of order < 0 is rejected;
order n > 0 sends n feedback messages 0.1 s apart (the sequence so far) and succeeds with the
sequence; order 13 aborts after its feedback; a cancel request is accepted and the goal ends
CANCELED at its next step. Prints one JSON line per goal event (``goal``, ``cancel``, ``end``).

``python rclpy_action_peer.py NAME --watch`` waits until NAME is in rclpy's action graph
(``{"action": [NAME, types]}``), subscribes to its feedback and status topics, reports
whether an rclpy ActionClient finds its server in 3 s (``{"server_ready": bool}``), then prints
``{"feedback": [goal id hex, sequence]}`` and ``{"status": [[goal id hex, status], ...]}`` as
they come."""

from __future__ import annotations

import json
import sys
import time

import rclpy
from action_msgs.msg import GoalStatusArray
from rclpy.action import ActionClient, ActionServer, CancelResponse, GoalResponse
from rclpy.action import get_action_names_and_types
from rclpy.action.server import ServerGoalHandle
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from test_msgs.action import Fibonacci


def say(**kw: object) -> None:
    print(json.dumps(kw), flush=True)


def watch(node: Node, name: str) -> None:
    while True:
        rclpy.spin_once(node, timeout_sec=0.1)
        found = dict(get_action_names_and_types(node)).get(name)
        if found:
            say(action=[name, found])
            break
    node.create_subscription(
        Fibonacci.Impl.FeedbackMessage, f"{name}/_action/feedback",
        lambda m: say(feedback=[bytes(m.goal_id.uuid).hex(), list(m.feedback.sequence)]), 10)
    node.create_subscription(
        GoalStatusArray, f"{name}/_action/status",
        lambda m: say(status=[[bytes(s.goal_info.goal_id.uuid).hex(), s.status]
                              for s in m.status_list]),
        QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    say(server_ready=ActionClient(node, Fibonacci, name).wait_for_server(timeout_sec=3.0))
    rclpy.spin(node)


def main() -> None:
    name = sys.argv[1]
    rclpy.init()
    node = Node("peer_action")
    if "--watch" in sys.argv:
        watch(node, name)
        return

    def on_goal(req: Fibonacci.Goal) -> GoalResponse:
        say(goal=req.order)
        return GoalResponse.REJECT if req.order < 0 else GoalResponse.ACCEPT

    def on_cancel(_gh: ServerGoalHandle) -> CancelResponse:
        say(cancel=True)
        return CancelResponse.ACCEPT

    def execute(gh: ServerGoalHandle) -> Fibonacci.Result:
        order = gh.request.order
        seq = [0, 1]
        result = Fibonacci.Result()
        for _ in range(order):
            if gh.is_cancel_requested:
                gh.canceled()
                result.sequence = seq
                say(end="canceled")
                return result
            seq.append(seq[-1] + seq[-2])
            fb = Fibonacci.Feedback()
            fb.sequence = seq
            gh.publish_feedback(fb)
            time.sleep(0.1)
        result.sequence = seq
        if order == 13:
            gh.abort()
            say(end="aborted")
        else:
            gh.succeed()
            say(end="succeeded")
        return result

    ActionServer(node, Fibonacci, name, execute, goal_callback=on_goal,
                 cancel_callback=on_cancel, callback_group=ReentrantCallbackGroup())
    say(ready=node.get_name())
    ex = MultiThreadedExecutor(4)
    ex.add_node(node)
    ex.spin()


if __name__ == "__main__":
    main()
