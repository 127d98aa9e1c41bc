"""galileo_msgs: the robot API's status and native commands (specs/robot-api.md §4, §12)."""

from __future__ import annotations

__all__: list[str] = []
