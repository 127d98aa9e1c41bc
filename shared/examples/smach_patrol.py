"""A patrol state machine, driven by topics and watched with `zenros smach show`.

The machine waits in IDLE for ``start`` on ``~/command``; PATROL then visits each waypoint
(publishing it on ``~/goal`` and waiting for ``~/arrived``) while STOP watches for
``stop``; whichever ends first preempts the other; COUNT adds a lap; back to IDLE::

    python -m zenros.examples.smach_patrol
    zenros smach show
    zenros topic pub /smach_patrol/command std_msgs/String '{data: start}' --once
    zenros topic pub /smach_patrol/arrived std_msgs/Empty --once     # once per waypoint
    zenros topic pub /smach_patrol/command std_msgs/String '{data: stop}' --once
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from zenros import Node, run
from zenros.msgs.geometry_msgs import Point
from zenros.msgs.std_msgs import Empty, String
from zenros.pubsub import Publisher
from zenros.smach import (
    CBState,
    Concurrence,
    ContainerEvent,
    Execution,
    IntrospectionServer,
    Iterator,
    MonitorState,
    StateMachine,
    UserDataAccess,
)


def until_word(word: str) -> Callable[[UserDataAccess, String], bool]:
    """A MonitorState condition that holds until ``word`` arrives (then: outcome "invalid")."""
    return lambda userdata, msg: msg.data != word


def build_patrol(node: Node, waypoints: Sequence[Sequence[float]],
                 goals: Publisher[Point]) -> StateMachine:
    """The machine: IDLE -> PATROL (TOUR of VISITs, alongside STOP) -> COUNT -> IDLE."""

    def send(userdata: UserDataAccess) -> str:
        x, y = userdata.waypoint
        node.logger.info("heading for (%g, %g)", x, y)
        goals.publish(Point(x=float(x), y=float(y)))
        return "sent"

    visit = StateMachine(outcomes=["succeeded", "preempted"], input_keys=["waypoint"])
    visit.add("SEND", CBState(send, outcomes=["sent"], input_keys=["waypoint"]),
              transitions={"sent": "ARRIVE"})
    visit.add("ARRIVE", MonitorState(node, "~/arrived", Empty, lambda ud, msg: False),
              transitions={"invalid": "succeeded", "valid": "ARRIVE"})

    tour = Iterator(outcomes=["done", "preempted"], it=lambda: [list(p) for p in waypoints],
                    it_label="waypoint", exhausted_outcome="done")
    tour.set_contained_state("VISIT", visit, loop_outcomes=["succeeded"])

    patrol = Concurrence(
        outcomes=["done", "stopped", "preempted"], default_outcome="done",
        outcome_map={"stopped": {"STOP": "invalid"}, "done": {"TOUR": "done"}},
        child_termination_cb=lambda outcomes: True,  # the first to end stops the other
    )
    patrol.add("TOUR", tour)
    patrol.add("STOP", MonitorState(node, "~/command", String, until_word("stop")))

    def count(userdata: UserDataAccess) -> str:
        userdata.laps = userdata.laps + 1
        node.logger.info("lap %d done", userdata.laps)
        return "succeeded"

    root = StateMachine(outcomes=["preempted"])
    root.userdata.laps = 0
    root.add("IDLE", MonitorState(node, "~/command", String, until_word("start")),
             transitions={"invalid": "PATROL", "valid": "IDLE"})
    root.add("PATROL", patrol, transitions={"done": "COUNT", "stopped": "IDLE"})
    root.add("COUNT", CBState(count, outcomes=["succeeded"], io_keys=["laps"]),
             transitions={"succeeded": "IDLE"})
    return root


class SmachPatrol(Node):
    """Runs the patrol machine in a thread, with an introspection server on ~/smach."""

    node_name = "smach_patrol"

    def setup(self) -> None:
        waypoints = self.declare_parameter("waypoints", [[1.0, 0.0], [2.0, 1.0]])
        goals = self.create_publisher(Point, "~/goal")
        self.machine = build_patrol(self, waypoints, goals)
        self.machine.add_listener(self.on_event)
        self.introspection = IntrospectionServer(self, self.machine)
        self.execution = self.machine.execute_in_thread()
        self.execution.add_done_callback(self.on_done)

    def on_event(self, event: ContainerEvent) -> None:
        if event.path == "/" and event.kind == "transition":
            self.logger.info("%s -> %s (%s)", event.label, event.target, event.outcome)

    def on_done(self, execution: Execution) -> None:
        error = execution.future.exception()
        if error is not None:
            self.logger.error("machine failed: %s", error)
        else:
            self.logger.info("machine ended: %s", execution.result())

    def close(self) -> None:
        """Preempt the machine and wait for it (its states use this node), then close."""
        execution = getattr(self, "execution", None)
        if execution is not None and not execution.done():
            execution.request_preempt()
            if not execution.join(5.0):
                self.logger.warning("the machine did not stop within 5 s of its preempt")
        super().close()


if __name__ == "__main__":
    run(SmachPatrol)
