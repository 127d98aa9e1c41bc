"""The aggregated tree as text (``zenros diag``) and as plain data (the robot API)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..msgs.diagnostic_msgs import DiagnosticStatus
from .status import LEVEL_NAMES

__all__ = ["format_tree", "tree_data"]


def _level(level: int) -> str:
    return LEVEL_NAMES.get(level, f"level {level}").upper()


def format_tree(statuses: Sequence[DiagnosticStatus], top: DiagnosticStatus | None = None, *,
                values: bool = False) -> str:
    """One line per status of ``/diagnostics_agg``, indented by its depth in the path::

        Motors                 OK       OK
          left wheel           OK       Desired frequency met

    With ``values``, each status's key/values follow it, one deeper."""
    rows: list[tuple[str, str, str]] = []
    if top is not None:
        rows.append(("(robot)", _level(top.level), ""))
    for s in statuses:
        parts = [p for p in s.name.split("/") if p]
        indent = "  " * max(0, len(parts) - 1)
        rows.append((indent + (parts[-1] if parts else s.name), _level(s.level), s.message))
        if values:
            rows += [(indent + "    " + kv.key, "", kv.value) for kv in s.values]
    if not rows:
        return "(no diagnostics)"
    width = max(len(r[0]) for r in rows) + 2
    return "\n".join(f"{name:<{width}}{lvl:<9}{msg}".rstrip() for name, lvl, msg in rows)


def tree_data(statuses: Sequence[DiagnosticStatus]) -> list[dict[str, Any]]:
    """The statuses as JSON-ready dicts: name, level (as a word), message, hardware_id,
    values."""
    return [{"name": s.name, "level": LEVEL_NAMES.get(s.level, str(s.level)),
             "message": s.message, "hardware_id": s.hardware_id,
             "values": {kv.key: kv.value for kv in s.values}} for s in statuses]
