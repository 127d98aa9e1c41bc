"""A LifecycleNode over real Zenoh: another session drives it through ROS 2's services and
sees its transition events; lifecycle publishers stay silent until the node is active."""

from __future__ import annotations

from typing import Any

import pytest
from zenros.lifecycle import (
    InvalidTransitionError,
    LifecycleNode,
    LifecycleState,
    TransitionCallbackReturn,
)
from zenros.msgs.bond import Status
from zenros.msgs.lifecycle_msgs import (
    ChangeState,
    ChangeStateRequest,
    GetAvailableStates,
    GetAvailableStatesRequest,
    GetAvailableTransitions,
    GetAvailableTransitionsRequest,
    GetState,
    GetStateRequest,
    Transition,
    TransitionEvent,
)
from zenros.msgs.std_msgs import String
from zenros.testing import Collector, wait_for

R = TransitionCallbackReturn


class Talker(LifecycleNode):
    fail_activate = False
    raise_on_configure = False

    def setup(self) -> None:
        self.calls: list[tuple[str, str]] = []
        self.pub = self.create_lifecycle_publisher(String, "chatter")

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.calls.append(("configure", state.label))
        if self.raise_on_configure:
            raise RuntimeError("no device")
        return super().on_configure(state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.calls.append(("activate", state.label))
        return R.FAILURE if self.fail_activate else super().on_activate(state)

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.calls.append(("error", state.label))
        return R.SUCCESS


def _change(client: Any, label: str = "", tid: int = 0) -> bool:
    res = client.call(ChangeStateRequest(transition=Transition(id=tid, label=label)), timeout=10)
    return bool(res.success)


@pytest.fixture
def rig(make_node: Any) -> tuple[Talker, Any, Collector[TransitionEvent]]:
    node: Talker = make_node("talker", 0, Talker)
    client = make_node("driver", 1)
    events: Collector[TransitionEvent] = Collector()
    client.create_subscription(TransitionEvent, "/talker/transition_event", events)
    change = client.create_client(ChangeState, "/talker/change_state")
    assert change.wait_for_service(10)
    assert node._events is not None and node._events.wait_for_subscribers(1, 10)
    return node, change, events


def test_a_client_drives_the_node_and_sees_two_events_per_request(
        rig: tuple[Talker, Any, Collector[TransitionEvent]], make_node: Any) -> None:
    node, change, events = rig
    client = make_node("reader", 1)
    get_state = client.create_client(GetState, "/talker/get_state")
    assert get_state.call(GetStateRequest(), timeout=10).current_state.label == "unconfigured"
    assert _change(change, "configure")
    assert _change(change, tid=Transition.TRANSITION_ACTIVATE)
    assert get_state.call(GetStateRequest(), timeout=10).current_state.id == 3
    assert events.wait(4, 10)
    steps = [(e.start_state.label, e.goal_state.label, e.transition.id) for e in events.items]
    assert steps == [("unconfigured", "configuring", 1), ("configuring", "inactive", 10),
                     ("inactive", "activating", 3), ("activating", "active", 30)]
    assert node.calls == [("configure", "unconfigured"), ("activate", "inactive")]
    # refused: not valid from active; the state stays, no event
    assert not _change(change, "configure")
    assert node.current_state.label == "active"
    avail = client.create_client(GetAvailableTransitions, "/talker/get_available_transitions")
    got = avail.call(GetAvailableTransitionsRequest(), timeout=10).available_transitions
    assert [(t.transition.label, t.transition.id, t.goal_state.label) for t in got] == [
        ("deactivate", 4, "deactivating"), ("shutdown", 7, "shuttingdown")]
    graph = client.create_client(GetAvailableTransitions, "/talker/get_transition_graph")
    assert len(graph.call(GetAvailableTransitionsRequest(), timeout=10)
               .available_transitions) == 25
    states = client.create_client(GetAvailableStates, "/talker/get_available_states")
    labels = [s.label for s in states.call(GetAvailableStatesRequest(), timeout=10)
              .available_states]
    assert labels[:5] == ["unknown", "unconfigured", "inactive", "active", "finalized"]
    assert len(labels) == 11
    assert _change(change, "shutdown")
    assert node.current_state.label == "finalized"
    assert events.wait(6, 10)
    assert len(events) == 6


def test_failure_answers_false_and_an_exception_goes_through_errorprocessing(
        rig: tuple[Talker, Any, Collector[TransitionEvent]]) -> None:
    node, change, events = rig
    node.raise_on_configure = True
    assert not _change(change, "configure")
    assert events.wait(3, 10)
    assert [e.goal_state.label for e in events.items] == [
        "configuring", "errorprocessing", "unconfigured"]
    assert node.calls == [("configure", "unconfigured"), ("error", "unconfigured")]
    node.raise_on_configure = False
    node.fail_activate = True
    assert _change(change, "configure")
    assert not _change(change, "activate")  # FAILURE: back to inactive, false
    assert node.current_state.label == "inactive"


def test_trigger_methods_and_invalid_ones_raise(make_node: Any) -> None:
    node: Talker = make_node("solo", 0, Talker)
    assert node.trigger_configure() is R.SUCCESS
    with pytest.raises(InvalidTransitionError):
        node.trigger_configure()
    assert node.trigger_activate() is R.SUCCESS
    assert node.trigger_deactivate() is R.SUCCESS
    assert node.trigger_cleanup() is R.SUCCESS
    assert node.current_state == LifecycleState("unconfigured", 1)


def test_lifecycle_publisher_is_silent_until_active_and_warns_once(
        make_node: Any, caplog: pytest.LogCaptureFixture) -> None:
    node: Talker = make_node("pub", 0, Talker, parameter_overrides={"bond_heartbeat_period": 0.0})
    listener = make_node("listener", 1)
    got: Collector[String] = Collector()
    listener.create_subscription(String, "/chatter", got)
    assert node.pub.wait_for_subscribers(1, 10)
    node.pub.publish(String(data="early"))
    node.pub.publish(String(data="early2"))
    assert sum("not activated" in r.message for r in caplog.records) == 1
    node.trigger_configure()
    node.trigger_activate()
    node.pub.publish(String(data="live"))
    assert got.wait(1, 10)
    node.trigger_deactivate()
    node.pub.publish(String(data="late"))
    assert sum("not activated" in r.message for r in caplog.records) == 2  # once per spell
    node.trigger_activate()
    node.pub.publish(String(data="live2"))
    assert got.wait(2, 10)
    assert [m.data for m in got.items] == ["live", "live2"]


def test_an_active_node_sends_bond_heartbeats(make_node: Any) -> None:
    node: Talker = make_node("bonded", 0, Talker,
                             parameter_overrides={"bond_heartbeat_period": 0.05})
    watcher = make_node("watcher", 1)
    beats: Collector[Status] = Collector()
    watcher.create_subscription(Status, "/bond", beats)
    node.trigger_configure()
    assert not wait_for(lambda: len(beats) > 0, 0.3)  # inactive: no heartbeat
    node.trigger_activate()
    assert beats.wait(3, 10)
    assert {(b.id, b.active) for b in beats.items} == {("bonded", True)}
    node.trigger_deactivate()
    assert wait_for(lambda: not beats.items[-1].active, 10)
    node.trigger_activate()
    n = len(beats)
    assert wait_for(lambda: len(beats) > n and beats.items[-1].active, 10)
    node.close()  # an active node that closes leaves its bond
    assert wait_for(lambda: not beats.items[-1].active, 10)
