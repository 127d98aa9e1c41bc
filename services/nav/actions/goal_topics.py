"""GoalTopics: goals given on topics, as Nav2's ``goal_pose`` (RViz's "2D Goal Pose") and
zenros's ``patrol_goal``: a goal without a goal handle, so a bag can hold it and a
deterministic replay can feed it (docs/replay.md).

A message on ``goal_pose`` (geometry_msgs/PoseStamped, in ``map`` or empty frame) starts
navigating there, preempting whatever ran; one on ``patrol_goal`` (zenros_msgs/PatrolGoal)
starts a patrol of a path's nav points. Neither reports a result: ``nav/status`` and the
robot's motion do. A bad goal is logged and ignored; an inactive nav ignores goals.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from zenros.errors import GoalRejectedError, ZenrosError
from zenros.msgs.geometry_msgs import PoseStamped
from zenros.msgs.zenros_msgs.nav import PatrolGoal
from zenros.se2 import Pose2

from ..core import NavCore
from ..motion.patrol import Patrol
from .convert import pose2_from_msg
from .navigation import NAV_CODES

__all__ = ["GoalTopics"]


class GoalTopics:
    def __init__(self, core: NavCore, logger: logging.Logger,
                 refusal: Callable[[], str]) -> None:
        self.core, self.logger, self.refusal = core, logger, refusal

    def on_goal_pose(self, msg: PoseStamped) -> None:
        why = self.refusal()
        if why:
            self.logger.warning("goal_pose ignored: %s", why)
            return
        frame = msg.header.frame_id.lstrip("/")
        if frame not in ("", "map"):
            self.logger.warning("goal_pose in frame %r ignored: it must be in map", frame)
            return
        try:
            target = pose2_from_msg(msg.pose)
        except ValueError as exc:
            self.logger.warning("goal_pose ignored: %s", exc)
            return
        self.logger.info("goal_pose: navigating to (%.2f, %.2f, %.2f)", target.x, target.y,
                         target.theta)
        self.core.start(self.core.make_nav(target, NAV_CODES))

    def on_patrol_goal(self, msg: PatrolGoal) -> None:
        why = self.refusal()
        if why:
            self.logger.warning("patrol_goal ignored: %s", why)
            return
        try:
            _, points = self.core.records.nav_points(msg.map_name, msg.path_name)
            b = Patrol([Pose2(p.x, p.y, p.theta) for p in points], self.core.make_nav,
                       loops=msg.loops, wait_time=msg.wait_time, start_index=msg.start_index)
        except (ZenrosError, GoalRejectedError, ValueError, KeyError) as exc:
            self.logger.warning("patrol_goal ignored: %s", exc)
            return
        self.logger.info("patrol_goal: patrolling %d nav points of path %r", len(points),
                         msg.path_name)
        self.core.start(b)
