"""The lifecycle manager's commands in one process over real Zenoh: Nav2's order (configure
all, then activate all; down in reverse), is_active, and the aborts (a node that fails, a
node that never bonds)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest
from zenros.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from zenros.lifecycle.manager import LifecycleManager
from zenros.msgs.nav2_msgs import ManageLifecycleNodes, ManageLifecycleNodesRequest
from zenros.msgs.std_srvs import Trigger, TriggerRequest

Cmd = ManageLifecycleNodesRequest
ORDER: list[tuple[str, str]] = []


class Managed(LifecycleNode):
    refuse_configure = False

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        ORDER.append((self.name, "configure"))
        if self.refuse_configure:
            return TransitionCallbackReturn.FAILURE
        return super().on_configure(state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        ORDER.append((self.name, "activate"))
        return super().on_activate(state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        ORDER.append((self.name, "deactivate"))
        return super().on_deactivate(state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        ORDER.append((self.name, "cleanup"))
        return super().on_cleanup(state)


@pytest.fixture
def rig(make_node: Any) -> tuple[list[Managed], LifecycleManager, Callable[[int], bool]]:
    ORDER.clear()
    nodes = [make_node(n, 0, Managed, parameter_overrides={"bond_heartbeat_period": 0.05})
             for n in ("a", "b", "c")]
    mgr: LifecycleManager = make_node("lifecycle_manager", 1, LifecycleManager,
                                      parameter_overrides={"node_names": ["a", "b", "c"],
                                                           "bond_timeout": 2.0,
                                                           "service_timeout": 5.0})
    client = make_node("operator", 1).create_client(ManageLifecycleNodes,
                                                    "/lifecycle_manager/manage_nodes")
    assert client.wait_for_service(10)

    def command(c: int) -> bool:
        return bool(client.call(Cmd(command=c), timeout=30).success)

    return nodes, mgr, command


def _states(nodes: list[Managed]) -> list[str]:
    return [n.current_state.label for n in nodes]


def test_startup_pause_resume_reset_shutdown_in_nav2s_order(
        rig: tuple[list[Managed], LifecycleManager, Callable[[int], bool]],
        make_node: Any) -> None:
    nodes, mgr, command = rig
    is_active = make_node("asker", 1).create_client(Trigger, "/lifecycle_manager/is_active")
    assert not is_active.call(TriggerRequest(), timeout=10).success
    assert command(Cmd.STARTUP)
    assert ORDER == [("a", "configure"), ("b", "configure"), ("c", "configure"),
                     ("a", "activate"), ("b", "activate"), ("c", "activate")]
    assert _states(nodes) == ["active"] * 3
    assert is_active.call(TriggerRequest(), timeout=10).success
    ORDER.clear()
    assert command(Cmd.PAUSE)
    assert ORDER == [("c", "deactivate"), ("b", "deactivate"), ("a", "deactivate")]
    assert not mgr.active
    assert command(Cmd.RESUME)
    assert _states(nodes) == ["active"] * 3 and mgr.active
    ORDER.clear()
    assert command(Cmd.RESET)
    assert ORDER == [("c", "deactivate"), ("b", "deactivate"), ("a", "deactivate"),
                     ("c", "cleanup"), ("b", "cleanup"), ("a", "cleanup")]
    assert _states(nodes) == ["unconfigured"] * 3
    assert command(Cmd.CONFIGURE)
    assert _states(nodes) == ["inactive"] * 3
    assert command(Cmd.CLEANUP)
    assert command(Cmd.SHUTDOWN)
    assert _states(nodes) == ["finalized"] * 3
    assert not command(99)  # unknown command: refused


def test_a_failing_node_aborts_startup(
        rig: tuple[list[Managed], LifecycleManager, Callable[[int], bool]]) -> None:
    nodes, mgr, command = rig
    nodes[1].refuse_configure = True
    assert not command(Cmd.STARTUP)
    assert ORDER == [("a", "configure"), ("b", "configure")]  # c is never asked
    assert _states(nodes) == ["inactive", "unconfigured", "unconfigured"]
    assert not mgr.active


def test_a_node_without_heartbeat_fails_to_bond(make_node: Any) -> None:
    ORDER.clear()
    make_node("mute", 0, Managed, parameter_overrides={"bond_heartbeat_period": 0.0})
    mgr: LifecycleManager = make_node("mgr", 1, LifecycleManager, parameter_overrides={
        "node_names": ["mute"], "bond_timeout": 0.4})
    assert not mgr.startup()
    assert not mgr.active
    mgr_off: LifecycleManager = make_node("mgr_off", 1, LifecycleManager, parameter_overrides={
        "node_names": ["mute"], "bond_timeout": 0.0})  # 0: bonds off
    assert mgr_off.reset() and mgr_off.startup()
