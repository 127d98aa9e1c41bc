"""A lifecycle manager over real processes: it brings three managed nodes up in order, and
when one is killed (SIGKILL by PID) it takes the others down, reports it, and brings all of
them up again once the dead one is back (Nav2's respawn behaviour)."""

from __future__ import annotations

import signal
import sys
from collections.abc import Callable, Iterator

import pytest
from zenros import Node
from zenros.context import Context
from zenros.msgs.lifecycle_msgs import GetState, GetStateRequest, TransitionEvent
from zenros.msgs.zenros_msgs import LifecycleManagerStatus
from zenros.qos import QOS_LATCHED
from zenros.testing import Collector, Proc, wait_for

pytestmark = pytest.mark.system

NAMES = ["cam", "planner", "driver"]


@pytest.fixture
def watcher(observer: Context) -> Iterator[Node]:
    node = Node("lifecycle_test_watcher", context=observer)
    try:
        yield node
    finally:
        node.close()


def _talker(router: str, prefix: str, name: str) -> Proc:
    return Proc([sys.executable, "-m", "zenros.examples.lifecycle_talker", "-e", router,
                 "--prefix", prefix, "--name", name, "-p", "bond_heartbeat_period:=0.1"])


def _state(watcher: Node, name: str) -> str:
    c = watcher.create_client(GetState, f"/{name}/get_state")
    try:
        return str(c.call(GetStateRequest(), timeout=10).current_state.label)
    finally:
        watcher.destroy(c)


def test_manager_brings_nodes_up_in_order_and_down_when_one_dies(
        router: str, prefix: str, watcher: Node, procs: list[Proc]) -> None:
    events: list[tuple[int, str, str]] = []

    def record(name: str) -> Callable[[TransitionEvent], None]:
        return lambda e: events.append((e.timestamp, name, e.goal_state.label))

    for n in NAMES:
        watcher.create_subscription(TransitionEvent, f"/{n}/transition_event", record(n))
    status: Collector[LifecycleManagerStatus] = Collector()
    watcher.create_subscription(LifecycleManagerStatus, "/lifecycle_manager/status", status,
                                QOS_LATCHED)
    nodes = {n: _talker(router, prefix, n) for n in NAMES}
    procs.extend(nodes.values())
    manager = Proc([sys.executable, "-m", "zenros.lifecycle.manager", "-e", router,
                    "--prefix", prefix, "-p", f"node_names:=[{', '.join(NAMES)}]",
                    "-p", "autostart:=true", "-p", "bond_timeout:=1.5",
                    "-p", "bond_respawn_max_duration:=60.0"])
    procs.append(manager)

    def last() -> LifecycleManagerStatus | None:
        return status.items[-1] if status.items else None

    assert wait_for(lambda: (s := last()) is not None and s.state == "active", 40), \
        manager.output
    # configure all in order, then activate all in order
    ups = [(n, g) for _, n, g in sorted(events) if g in ("configuring", "activating")]
    assert ups == [(n, "configuring") for n in NAMES] + [(n, "activating") for n in NAMES]
    assert all(_state(watcher, n) == "active" for n in NAMES)

    nodes["planner"].signal(signal.SIGKILL)  # by PID
    assert wait_for(lambda: any(s.state == "down" and s.lost == "planner"
                                for s in status.items), 30), manager.output
    assert wait_for(lambda: (s := last()) is not None and s.state == "respawning", 60), \
        manager.output
    assert _state(watcher, "cam") == "unconfigured"
    assert _state(watcher, "driver") == "unconfigured"
    downs = [(n, g) for _, n, g in sorted(events) if g == "deactivating"]
    assert downs == [("driver", "deactivating"), ("cam", "deactivating")]  # reverse order
    assert "CRITICAL FAILURE: SERVER planner IS DOWN" in manager.output

    procs.append(_talker(router, prefix, "planner"))  # respawned (as launch's respawn would)
    assert wait_for(lambda: (s := last()) is not None and s.state == "active", 40), \
        manager.output
    assert all(_state(watcher, n) == "active" for n in NAMES)
