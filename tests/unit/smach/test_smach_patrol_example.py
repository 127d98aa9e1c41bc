"""The patrol example of docs/smach.md: every container kind working together."""

from __future__ import annotations

from zenros.smach import (
    CBState,
    Concurrence,
    ConditionState,
    ContainerEvent,
    Iterator,
    State,
    StateMachine,
    UserData,
    UserDataAccess,
)
from zenros.smach.doubles import WaitForPreempt


class GoTo(State):
    def __init__(self) -> None:
        super().__init__(outcomes=["succeeded", "aborted", "preempted"],
                         input_keys=["target"], output_keys=["visited"])
        self.visits: list[object] = []

    def execute(self, userdata: UserDataAccess) -> str:
        if self.preempt_requested():
            self.service_preempt()
            return "preempted"
        self.visits.append(userdata.target)
        userdata.visited = userdata.target
        return "succeeded"


def build(go: State) -> StateMachine:
    tour = Iterator(outcomes=["done", "aborted", "preempted"],
                    it=lambda: [(1.0, 0.0), (2.0, 1.0), (0.0, 0.0)],
                    it_label="waypoint", exhausted_outcome="done")
    tour.set_contained_state("GO", go, loop_outcomes=["succeeded"],
                             remapping={"target": "waypoint", "visited": "last"})
    guarded = Concurrence(
        outcomes=["done", "low_battery", "preempted"], default_outcome="done",
        input_keys=["battery"],
        outcome_map={"low_battery": {"BATTERY": "false"}, "done": {"TOUR": "done"}},
        child_termination_cb=lambda outcomes: True,
    )
    guarded.add("TOUR", tour)
    guarded.add("BATTERY", ConditionState(lambda ud: ud.battery > 0.2, input_keys=["battery"],
                                          poll_interval=0.05, max_checks=-1))
    patrol = StateMachine(outcomes=["finished", "charging", "preempted"], input_keys=["battery"])
    patrol.add("PATROL", guarded, transitions={"done": "finished", "low_battery": "DOCK"})
    patrol.add("DOCK", CBState(lambda ud: "succeeded", outcomes=["succeeded"]),
               transitions={"succeeded": "charging"})
    return patrol


def test_full_battery_finishes_the_tour() -> None:
    go = GoTo()
    patrol = build(go)
    assert patrol.execute(UserData({"battery": 0.9})) == "finished"
    assert go.visits == [(1.0, 0.0), (2.0, 1.0), (0.0, 0.0)]
    tour = patrol.find("PATROL/TOUR")
    assert isinstance(tour, Iterator)
    assert tour.get_status().userdata["last"] == (0.0, 0.0)


def test_low_battery_docks() -> None:
    patrol = build(GoTo())
    events: list[ContainerEvent] = []
    patrol.add_listener(events.append)
    assert patrol.execute(UserData({"battery": 0.1})) == "charging"
    assert ("/", "PATROL", "low_battery", "DOCK") in [
        (e.path, e.label, e.outcome, e.target) for e in events]


def test_preempting_the_patrol_mid_tour() -> None:
    waiting = WaitForPreempt(outcomes=["succeeded", "aborted"], input_keys=["target"],
                             output_keys=["visited"])
    patrol = build(waiting)
    run = patrol.execute_in_thread(UserData({"battery": 0.9}))
    assert waiting.entered.wait(5)
    assert sorted(patrol.get_status().active_paths) == ["/PATROL/BATTERY", "/PATROL/TOUR/GO"]
    run.request_preempt()
    assert run.result(5) == "preempted"
