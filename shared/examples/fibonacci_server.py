"""Serves example_interfaces/Fibonacci on /fibonacci: one number per `period` seconds, each
published as feedback, as in the ROS 2 action tutorial."""

from __future__ import annotations

from zenros import GoalRejectedError, Node, run
from zenros.action import ActionServer, GoalResponse, ServerGoalHandle
from zenros.msgs.example_interfaces import (
    Fibonacci,
    FibonacciFeedback,
    FibonacciGoal,
    FibonacciResult,
)

MAX_ORDER = 10_000


class FibonacciServer(Node):
    """Computes Fibonacci sequences slowly, with feedback, cancel and preemption."""

    node_name = "fibonacci_server"

    def setup(self) -> None:
        self.period = float(self.declare_parameter("period", 0.5))
        policy = str(self.declare_parameter("policy", "simple"))
        self.server = ActionServer(self, Fibonacci, "fibonacci", self.execute,
                                   self.on_goal, policy=policy)

    def on_goal(self, goal: FibonacciGoal) -> GoalResponse:
        if not 0 <= goal.order <= MAX_ORDER:
            raise GoalRejectedError(f"order must be in [0, {MAX_ORDER}], got {goal.order}")
        return GoalResponse.ACCEPT

    def execute(self, goal_handle: ServerGoalHandle[FibonacciGoal]) -> FibonacciResult:
        seq = [0, 1]
        for i in range(1, goal_handle.request.order):
            if goal_handle.wait_for_cancel(self.period):
                goal_handle.canceled()
                return FibonacciResult(sequence=seq)
            seq.append(seq[i] + seq[i - 1])
            goal_handle.publish_feedback(FibonacciFeedback(sequence=list(seq)))
        goal_handle.succeed()
        return FibonacciResult(sequence=seq)


if __name__ == "__main__":
    run(FibonacciServer)
