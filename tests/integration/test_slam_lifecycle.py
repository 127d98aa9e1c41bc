"""The mapping node as a managed (lifecycle) node over real Zenoh, as Nav2's servers are:
with ``autostart`` off it waits unconfigured, ``slam/start`` is refused until it is active
(after waiting a moment for a manager), a lifecycle manager brings it up, pausing it
(deactivate) stops a mapping run and tells nav to leave mapping mode, and its diagnostics
say what state it is in."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

from zenros.diagnostics import WARN
from zenros.lifecycle.manager import LifecycleManager
from zenros.msgs.diagnostic_msgs import DiagnosticArray
from zenros.msgs.lifecycle_msgs import GetState, GetStateRequest
from zenros.msgs.nav2_msgs import ManageLifecycleNodes, ManageLifecycleNodesRequest
from zenros.msgs.zenros_msgs import slam as sm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.services.slam.node import SlamNode
from zenros.testing import Collector, wait_for


class NavStandIn:
    def __init__(self, node: Any) -> None:
        self.modes: list[sm.SetMappingModeRequest] = []
        node.create_service(sm.SetMappingMode, "nav/set_mapping_mode", self.on_mode)

    def on_mode(self, req: sm.SetMappingModeRequest) -> sm.SetMappingModeResponse:
        self.modes.append(req)
        return sm.SetMappingModeResponse()


def test_slam_waits_for_its_manager_and_stops_mapping_when_paused(
        make_node: Any, tmp_path: Path) -> None:
    slam = make_node("slam", 0, SlamNode, parameter_overrides={
        "autostart": False, "graph_dir": str(tmp_path)})
    user = make_node("user", 1)
    nav = NavStandIn(user)
    reports: Collector[DiagnosticArray] = Collector()
    user.create_subscription(DiagnosticArray, "/diagnostics", reports)
    start = user.create_client(sm.StartMapping, "slam/start")
    get_state = user.create_client(GetState, "slam/get_state")
    assert start.wait_for_service(10) and get_state.wait_for_service(10)
    assert get_state.call(GetStateRequest(), 10).current_state.label == "unconfigured"

    slam.activation_wait = 0.3
    refused = start.call(sm.StartMappingRequest(mode="laser"), timeout=10)
    assert refused.code == ResultCode.CONFLICT and "unconfigured, not active" in refused.message

    # a start that comes while the manager brings the node up waits for it
    slam.activation_wait = 10.0
    answers: list[Any] = []
    caller = threading.Thread(target=lambda: answers.append(
        start.call(sm.StartMappingRequest(mode="laser"), timeout=15)))
    caller.start()
    manager = make_node("lifecycle_manager", 0, LifecycleManager, parameter_overrides={
        "node_names": ["slam"], "autostart": True})
    caller.join(20)
    assert answers and answers[0].code == ResultCode.OK, answers
    assert slam.current_state.label == "active"
    assert wait_for(lambda: slam.state.state == "mapping", 10)

    # PAUSE deactivates: the run stops, nav is told to leave mapping mode, start is refused
    manage = user.create_client(ManageLifecycleNodes, "lifecycle_manager/manage_nodes")
    assert manage.wait_for_service(10)
    assert manage.call(ManageLifecycleNodesRequest(
        command=ManageLifecycleNodesRequest.PAUSE), timeout=15).success
    assert slam.current_state.label == "inactive"
    assert wait_for(lambda: slam.state.state == "idle", 10)
    assert wait_for(lambda: any(not m.enable for m in nav.modes), 10)
    slam.activation_wait = 0.3
    assert start.call(sm.StartMappingRequest(mode="laser"), timeout=10).code == \
        ResultCode.CONFLICT
    # its diagnostics say so (slam: mapping, on /diagnostics)
    assert wait_for(lambda: any(
        s.name == "slam: mapping" and s.level == WARN and s.message.startswith("inactive")
        for a in reports.items for s in a.status), 10), reports.items[-1:]
    assert manage.call(ManageLifecycleNodesRequest(
        command=ManageLifecycleNodesRequest.RESUME), timeout=15).success
    assert start.call(sm.StartMappingRequest(mode="laser"), timeout=10).code == ResultCode.OK
    assert manager is not None
