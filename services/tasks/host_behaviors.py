"""The task actions that change the robot's host rather than move it (docs/tasks.md):
``change_setting_action`` (the gateway's ``/system/config``, set back at the task's end when
``init_settings`` says so) and ``roslaunch_action`` (a launch file zenros ships, run until
the task's end)."""

from __future__ import annotations

from typing import Any

from zenros.msgs.zenros_msgs.task_actions import ChangeSettingAction, RoslaunchAction

from .context import Context
from .outcome import Outcome

__all__ = ["change_setting", "roslaunch"]


def change_setting(ctx: Context, p: ChangeSettingAction) -> Outcome:
    """Set ``settings``; ``init_settings`` (checked first) are set when the task ends."""
    init: dict[str, Any] | None = p.init_settings if isinstance(p.init_settings, dict) else None
    if init is not None:
        checked = ctx.robot.change_settings(init, check_only=True)
        if checked.name != "complete":
            return Outcome("error", f"init_settings: {checked.reason}")
    out = ctx.robot.change_settings(p.settings)
    if out.name != "complete" or init is None:
        return out
    robot = ctx.robot

    def restore() -> None:
        back = robot.change_settings(init)
        if back.name != "complete":
            raise RuntimeError(f"change_setting_action: init_settings not set back: "
                               f"{back.reason}")

    ctx.at_end(restore)
    return Outcome("complete", f"{out.reason}; init_settings set back when the task ends")


def roslaunch(ctx: Context, p: RoslaunchAction) -> Outcome:
    """Start the launch; complete once its nodes are up. It is stopped when the task ends."""
    out, key = ctx.robot.launch(p.launch_cmd, ctx.cancelled)
    if key:
        robot = ctx.robot
        ctx.at_end(lambda: robot.stop_launch(key))
    return out
