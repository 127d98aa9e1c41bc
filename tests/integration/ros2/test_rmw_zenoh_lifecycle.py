"""A zenros LifecycleNode driven from ROS 2 through the rmw_zenoh bridge: an rmw_zenoh client
(`rmw_peer.RmwPeer`: rmw_zenoh's keys and tokens, the wheels' hashes, rclpy's CDR and
lifecycle_msgs classes) calls its ~/change_state, ~/get_state and
~/get_available_transitions, and an rmw_zenoh subscription gets its transition events, as
`ros2 lifecycle` on rmw_zenoh would."""

from __future__ import annotations

from typing import Any

import pytest
from zenros.lifecycle import LifecycleNode
from zenros.testing import Collector, wait_for

pytest.importorskip("rclpy", reason="ROS 2 wheels not installed (extra ros2)")
pytest.importorskip("lifecycle_msgs", reason="ros-lifecycle-msgs not installed (extra ros2)")

import rmw_peer  # noqa: F401  (puts rosref, tests/unit/ros2, on the path)
from rosref import ros_class

SRV = "lifecycle_msgs/srv"


def test_ros2_client_drives_a_zenros_lifecycle_node(make_rmw_rig: Any) -> None:
    _, bridge, peer, ctx = make_rmw_rig("lc_driver")
    lc = LifecycleNode("lc_node", context=ctx)
    try:
        events: Collector[Any] = Collector()
        peer.subscribe("/lc_node/transition_event", "lifecycle_msgs/msg/TransitionEvent", events)
        for name in ("change_state", "get_state", "get_available_transitions"):
            assert wait_for(lambda n=name: f"/lc_node/{n}" in bridge.services, 10)
        change = peer.client("/lc_node/change_state", f"{SRV}/ChangeState")
        get_state = peer.client("/lc_node/get_state", f"{SRV}/GetState")
        avail = peer.client("/lc_node/get_available_transitions",
                            f"{SRV}/GetAvailableTransitions")
        transition = ros_class("lifecycle_msgs/msg/Transition")

        def change_to(**kw: Any) -> bool:
            req = ros_class(f"{SRV}/ChangeState_Request")(transition=transition(**kw))
            resp, sent, got = change.call(req, f"{SRV}/ChangeState_Response")
            assert got.sequence_id == sent.sequence_id
            return bool(resp.success)

        def state() -> str:
            resp, _, _ = get_state.call(ros_class(f"{SRV}/GetState_Request")(),
                                        f"{SRV}/GetState_Response")
            return str(resp.current_state.label)

        assert state() == "unconfigured"
        assert change_to(label="configure")
        assert change_to(id=transition.TRANSITION_ACTIVATE)
        assert state() == "active" and lc.current_state.label == "active"
        assert not change_to(label="configure")  # not from active: false, as rcl answers
        resp, _, _ = avail.call(ros_class(f"{SRV}/GetAvailableTransitions_Request")(),
                                f"{SRV}/GetAvailableTransitions_Response")
        assert [(t.transition.label, t.transition.id) for t in resp.available_transitions] == \
            [("deactivate", 4), ("shutdown", 7)]
        assert events.wait(4, 10)
        assert [e.goal_state.label for e in events.items[:4]] == [
            "configuring", "inactive", "activating", "active"]
    finally:
        lc.close()
