"""A sample on an action's feedback key that is not its FeedbackMessage is refused by type
when its encoding says so, and the log names who sent it (issue 21 item 8: "cannot decode
feedback: ... missing required field goal_id", with nothing to say where it came from)."""

from __future__ import annotations

import pytest
from zenros.action import ActionClient
from zenros.action.transport import encoding_for
from zenros.codec import codec_for
from zenros.context import Context
from zenros.msgs.nav2_msgs import DockRobot
from zenros.node import Node
from zenros.testing import wait_for


def test_bad_feedback_is_refused_and_its_sender_named(
        ctx_pair: list[Context], caplog: pytest.LogCaptureFixture) -> None:
    with Node("tasks", context=ctx_pair[0]) as user, Node("stray", context=ctx_pair[1]) as stray:
        client = ActionClient(user, DockRobot, "dock_robot")
        key = ctx_pair[1].keys.action("/dock_robot", "feedback")
        assert user.graph.wait_for_node("/stray", 10)
        inner = DockRobot.Feedback
        pub = ctx_pair[1].session.declare_publisher(key, encoding=encoding_for(inner))
        try:  # the bare Feedback, without the goal_id wrapper, as a wrong publisher sends it
            assert wait_for(lambda: (pub.put(codec_for(inner).encode(inner())), False)[1]
                            or "cannot decode feedback" in caplog.text, 10)
        finally:
            pub.undeclare()
        assert "type mismatch: expected nav2_msgs/DockRobot_FeedbackMessage, got " \
               "nav2_msgs/DockRobotFeedback" in caplog.text, caplog.text
        assert "from /stray" in caplog.text, caplog.text
        assert not client.closed
