"""The analyzers of the robot's own services: what the aggregator runs when its parameters
name none (``analyzers.*``)."""

from __future__ import annotations

from typing import Any

__all__ = ["ROBOT_ANALYZERS"]

_GA = "diagnostic_aggregator/GenericAnalyzer"


def _part(key: str, path: str, node: str, expected: list[str]) -> dict[str, Any]:
    return {f"analyzers.{key}.type": _GA, f"analyzers.{key}.path": path,
            f"analyzers.{key}.startswith": [f"{node}:"],
            f"analyzers.{key}.expected": [f"{node}: {e}" for e in expected],
            f"analyzers.{key}.remove_prefix": [node]}


ROBOT_ANALYZERS: dict[str, Any] = {
    **_part("chassis", "Chassis", "chassis", ["motors", "battery", "laser"]),
    **_part("navigation", "Navigation", "nav", ["localization", "goals"]),
    **_part("gateway", "Gateway", "gateway", ["front ends", "clients"]),
    # the mapping service runs only where the launch maps (robot.yaml mapping:=false has
    # none): its item is claimed, not expected
    **_part("mapping", "Mapping", "slam", []),
}
"""The chassis (motors, battery, laser), nav (localization, goals) and the gateway (front
ends, clients), each a branch whose items are expected: one that stops reporting shows
as "Missing" or STALE; and the mapping service (slam: mapping) where it runs."""
