"""The mapping service's diagnostics (``/diagnostics``): ``slam: mapping``, what it is doing,
its lifecycle state and how the mapper keeps up, reported through an `Updater`
(docs/diagnostics.md)."""

from __future__ import annotations

from typing import Any

from zenros.diagnostics import OK, WARN, DiagnosticStatusWrapper, Updater

__all__ = ["slam_diagnostics"]


def slam_diagnostics(node: Any) -> Updater:
    """An Updater on ``node`` (a `SlamNode`): ``mapping``."""
    up = Updater(node)
    up.setHardwareID("none")

    def mapping(stat: DiagnosticStatusWrapper) -> None:
        state, session = node.state, node.session
        scans, nodes, closures = session.counts()
        lifecycle = node.current_state.label
        if lifecycle != "active":
            stat.summary(WARN, f"{lifecycle}: not taking mapping runs")
        elif session.active and session.skipped:
            stat.summary(WARN, f"mapping: {session.skipped} scans skipped (the mapper did not "
                               "keep up)")
        elif state.message and state.state == "idle":
            stat.summary(WARN, f"idle; the last run said: {state.message}")
        else:
            stat.summary(OK, state.state if not session.paused else f"{state.state} (paused)")
        stat.add("lifecycle", lifecycle)
        stat.add("state", state.state)
        stat.add("mode", state.mode or "none")
        stat.add("scans", scans)
        stat.add("nodes", nodes)
        stat.add("loop closures", closures)
        stat.add("area (m2)", f"{state.area_m2:.1f}")

    up.add("mapping", mapping)
    return up
