"""Nav as a managed (lifecycle) node over real Zenoh, as Nav2's servers are: with
``autostart`` off its actions refuse goals until it is active (a goal sent while it is being
brought up waits for it), and deactivating it cancels the goal it is driving."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

from sim_robot import sim_robot
from zenros.action import ActionClient, GoalStatus
from zenros.errors import GoalRejectedError
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal
from zenros.se2 import Pose2
from zenros.services.nav.actions.convert import pose_stamped
from zenros.testing import wait_for


def _goal(x: float, y: float) -> NavigateToPoseGoal:
    return NavigateToPoseGoal(pose=pose_stamped(Pose2(x, y, 0.0), Time()))


def test_nav_refuses_goals_until_active_and_a_pause_cancels_the_drive(tmp_path: Path) -> None:
    with sim_robot(tmp_path, tasks=False, nav={"autostart": False}) as robot:
        nav = robot.nav
        assert nav.current_state.label == "unconfigured"
        client = ActionClient(robot.user, NavigateToPose, "navigate_to_pose")
        assert client.wait_for_server(10)
        nav.activation_wait = 0.3
        try:
            client.send_goal(_goal(2.0, 0.0), timeout=10)
            raise AssertionError("a goal was accepted by an unconfigured nav")
        except GoalRejectedError as exc:
            assert "not active" in str(exc) and "unconfigured" in str(exc)

        # a goal sent while a manager brings nav up waits for it and is served
        nav.activation_wait = 10.0
        handles: list[Any] = []
        sender = threading.Thread(target=lambda: handles.append(
            client.send_goal_async(_goal(6.0, 0.0))))
        sender.start()
        assert nav.trigger_configure().name == "SUCCESS"
        assert nav.trigger_activate().name == "SUCCESS"
        sender.join(20)
        handle = handles[0]
        assert wait_for(lambda: handle.accepted, 15)
        assert wait_for(lambda: nav.core.motion.active is not None, 15)

        # deactivating cancels the running goal; the robot stops
        assert nav.trigger_deactivate().name == "SUCCESS"
        result = handle.result(30)
        assert result.status == GoalStatus.CANCELED, result
        assert wait_for(lambda: nav.core.motion.active is None, 15)
        nav.activation_wait = 0.3
        try:
            client.send_goal(_goal(2.0, 0.0), timeout=10)
            raise AssertionError("a goal was accepted by an inactive nav")
        except GoalRejectedError as exc:
            assert "inactive" in str(exc)
