"""nav_status: the ``nav/status`` message from the core's state (for the gateway)."""

from __future__ import annotations

from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs.nav import NavStatus
from zenros.se2 import Pose2

from ..core import NavCore
from ..motion.docking import Dock, Undock
from ..motion.navigate import Navigate
from ..motion.patrol import Patrol
from .base import Ledger
from .convert import pose2_to_pose2d

__all__ = ["nav_status"]


def nav_status(core: NavCore, ledger: Ledger, stamp: Time) -> NavStatus:
    pose = core.localizer.pose()
    msg = NavStatus(header=Header(stamp=stamp, frame_id="map"),
                    map_name="" if core.mapping else core.maps.current,
                    localized=pose is not None, pose=pose2_to_pose2d(pose or Pose2()),
                    mapping=core.mapping)
    b = core.motion.active
    if b is None:
        msg.state = "charging" if core.charging else "idle"
        msg.goal_status, msg.error_code, msg.error_msg = ledger.last_outcome
        return msg
    msg.goal_status = 1
    cur = ledger.current
    if cur is not None and cur[1] is b and cur[2] is not None:
        msg.goal = pose2_to_pose2d(cur[2])
    nav = b.nav if isinstance(b, Patrol) else b if isinstance(b, Navigate) else None
    if isinstance(b, Dock):
        msg.state = "docking"
        msg.goal = pose2_to_pose2d(b.dock)
    elif isinstance(b, Undock):
        msg.state = "undocking"
    elif isinstance(b, Patrol):
        msg.state = "patrolling"
    else:
        msg.state = "recovering" if isinstance(b, Navigate) and b.state == "recovering" \
            else "navigating"
    if nav is not None and nav.distance_remaining == nav.distance_remaining:  # not NaN
        msg.target_distance = float(nav.distance_remaining)
    return msg
