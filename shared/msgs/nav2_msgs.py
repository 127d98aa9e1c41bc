"""nav2_msgs: Nav2's actions and services with Nav2's field names and error codes."""

from __future__ import annotations

__all__: list[str] = []
