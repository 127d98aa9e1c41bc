"""The robot's services report through zenros.diagnostics: chassis, nav and gateway statuses,
aggregated by the robot's own analyzers into one tree."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from sim_robot import GatewayRobot, gateway_robot
from zenros.diagnostics import ERROR, OK, STALE
from zenros.msgs.diagnostic_msgs import DiagnosticArray, DiagnosticStatus
from zenros.msgs.std_srvs import SetBool, SetBoolRequest
from zenros.services.diagnostics.node import AggregatorNode
from zenros.waiting import wait_until


@pytest.fixture(scope="module")
def robot(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[GatewayRobot, Any]]:
    with gateway_robot(tmp_path_factory.mktemp("diag")) as r:
        agg = AggregatorNode(context=r.contexts[-1], parameter_overrides={"pub_rate": 5.0})
        try:
            yield r, agg
        finally:
            agg.close()


def tree(trees: list[DiagnosticArray]) -> dict[str, DiagnosticStatus]:
    return {s.name: s for s in trees[-1].status} if trees else {}


def test_every_part_reports_and_the_robot_is_ok(robot: tuple[GatewayRobot, Any]) -> None:
    r, _ = robot
    trees: list[DiagnosticArray] = []
    r.user.create_subscription(DiagnosticArray, "/diagnostics_agg", trees.append)
    parts = ["/Chassis/motors", "/Chassis/battery", "/Chassis/laser",
             "/Navigation/localization", "/Navigation/goals",
             "/Gateway/front ends", "/Gateway/clients"]
    wait_until(lambda: all(tree(trees).get(p, DiagnosticStatus(level=STALE)).level == OK
                           for p in parts), 30)
    t = tree(trees)
    assert [s.name for s in trees[-1].status if s.name.count("/") == 1] == [
        "/Chassis", "/Gateway", "/Mapping", "/Navigation"]  # the analyzers, sorted
    assert t["/Chassis/laser"].message.endswith("Hz")
    assert {kv.key for kv in t["/Gateway/front ends"].values} >= {"REST", "Modbus"}
    assert t["/Navigation/localization"].message.startswith("localized")
    assert "/Other" not in t


def test_an_engaged_estop_turns_the_motors_the_robot_and_the_self_test_to_error(
        robot: tuple[GatewayRobot, Any]) -> None:
    r, _ = robot
    trees: list[DiagnosticArray] = []
    tops: list[DiagnosticStatus] = []
    r.user.create_subscription(DiagnosticArray, "/diagnostics_agg", trees.append)
    r.user.create_subscription(DiagnosticStatus, "/diagnostics_toplevel_state", tops.append)
    wait_until(lambda: r.http.get("/system/self_test").json()["motor_driver"] is True, 30)
    estop = r.user.create_client(SetBool, "/chassis/set_estop")
    assert estop.call(SetBoolRequest(data=True), timeout=10).success
    try:
        wait_until(lambda: tree(trees).get("/Chassis/motors", DiagnosticStatus()).message
                   == "e-stop engaged", 30)
        assert tree(trees)["/Chassis"].level == ERROR
        wait_until(lambda: tops and tops[-1].level == ERROR, 10)
        # GET /system/self_test answers from the tree: odometry still flows, the motors do not
        wait_until(lambda: r.http.get("/system/self_test").json()["motor_driver"] is False, 10)
        test = r.http.get("/system/self_test").json()
        assert test["lidar"] is True and test["battery"] is True and r.gw.topics.fresh("odom")
    finally:
        assert estop.call(SetBoolRequest(data=False), timeout=10).success
    wait_until(lambda: r.http.get("/system/self_test").json()["motor_driver"] is True, 30)
