"""zenros.diagnostics over real Zenoh: a node's Updater, the aggregator service's node, the tree."""

from __future__ import annotations

from typing import Any

from zenros import Node
from zenros.diagnostics import (
    ERROR,
    OK,
    STALE,
    WARN,
    FrequencyStatus,
    FrequencyStatusParam,
    Updater,
)
from zenros.msgs.diagnostic_msgs import DiagnosticArray, DiagnosticStatus
from zenros.services.diagnostics.node import AggregatorNode
from zenros.waiting import wait_until

ANALYZERS = {
    "analyzers.motors.type": "diagnostic_aggregator/GenericAnalyzer",
    "analyzers.motors.path": "Motors",
    "analyzers.motors.startswith": ["base: motor"],
    "analyzers.motors.remove_prefix": ["base"],
    "analyzers.laser.type": "diagnostic_aggregator/GenericAnalyzer",
    "analyzers.laser.path": "Laser",
    "analyzers.laser.expected": ["base: laser"],
}


class Base(Node):
    node_name = "base"

    def setup(self) -> None:
        self.updater = Updater(self, period=0.1)
        self.updater.setHardwareID("sim-base")
        self.temp = 40.0
        self.updater.add("motor left", self.check_motor)
        self.freq = FrequencyStatus(FrequencyStatusParam({"min": 1.0, "max": 1000.0}),
                                    "odom rate")
        self.updater.add(self.freq)

    def check_motor(self, stat: Any) -> None:
        stat.add("temperature", self.temp)
        if self.temp > 70:
            stat.summary(WARN, "hot")
        else:
            stat.summary(OK, "ok")


def test_updater_to_aggregated_tree(make_node: Any) -> None:
    raw: list[DiagnosticArray] = []
    watcher = make_node("watcher", 1)
    watcher.create_subscription(DiagnosticArray, "/diagnostics", raw.append)
    agg = make_node("diagnostic_aggregator", 1, cls=AggregatorNode,
                    parameter_overrides={"pub_rate": 10.0, **ANALYZERS})
    trees: list[DiagnosticArray] = []
    tops: list[DiagnosticStatus] = []
    watcher.create_subscription(DiagnosticArray, "/diagnostics_agg", trees.append)
    watcher.create_subscription(DiagnosticStatus, "/diagnostics_toplevel_state", tops.append)
    wait_until(lambda: agg.graph.subscribers("/diagnostics"), 10)
    base = make_node("base", 0, cls=Base)
    wait_until(lambda: any(s.name == "base: motor left" and s.message == "ok"
                           for a in raw for s in a.status), 10)
    first = next(s for a in raw for s in a.status if s.name == "base: motor left")
    assert (first.level, first.message) == (OK, "Node starting up")  # sent when added
    status = next(s for a in raw for s in a.status
                  if s.name == "base: motor left" and s.message == "ok")
    assert status.hardware_id == "sim-base"
    assert {kv.key: kv.value for kv in status.values} == {"temperature": "40.0"}

    def tree() -> dict[str, DiagnosticStatus]:
        return {s.name: s for s in trees[-1].status} if trees else {}

    wait_until(lambda: "/Motors/motor left" in tree() and "/Other/base: odom rate" in tree(),
               10)  # "odom rate": no analyzer claims it
    t = tree()
    # only the missing item under it: the branch is STALE (ROS: all stale), the robot ERROR
    assert (t["/Laser"].level, t["/Laser/base: laser"].message) == (STALE, "Missing")
    wait_until(lambda: tops and tops[-1].level == ERROR, 10)  # the laser is missing

    base.temp = 80.0
    base.updater.force_update()
    wait_until(lambda: tree().get("/Motors/motor left", DiagnosticStatus()).message == "hot", 10)
    assert tree()["/Motors"].level == WARN

    base.updater.broadcast(ERROR, "device gone")
    wait_until(lambda: any(s.message == "device gone" for a in raw for s in a.status), 10)
