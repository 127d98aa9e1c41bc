"""zenros_msgs for the tasks service (see DESIGN.md, "Robot interfaces")."""

from __future__ import annotations

__all__: list[str] = []
