"""Navigation's diagnostics (``/diagnostics``): localisation quality and goal failures,
reported through an `Updater` (docs/diagnostics.md)."""

from __future__ import annotations

from typing import Any

from zenros.diagnostics import ERROR, OK, WARN, DiagnosticStatusWrapper, Updater

__all__ = ["nav_diagnostics"]

FAILED = 3  # nav/status goal_status of a goal that failed (the ledger's last outcome)
ODOM_SILENT_S = 2.0  # no odometry for this long: the pose is not followed


def nav_diagnostics(node: Any) -> Updater:
    """An Updater on ``node`` (a `NavNode`): ``localization`` and ``goals``."""
    up = Updater(node)
    up.setHardwareID("none")
    core, ledger = node.core, node.ledger

    def localization(stat: DiagnosticStatusWrapper) -> None:
        loc, matcher = core.localizer, core.matcher
        age = (node.now().nanoseconds - loc.odom_stamp_ns) / 1e9 if loc.odom_stamp_ns else None
        score = core.match_score
        if loc.pose() is None:
            stat.summary(WARN, "not localized: no odometry or initial pose yet")
        elif age is not None and age > ODOM_SILENT_S:
            stat.summary(ERROR, f"odometry silent for {age:.1f} s")
        elif loc.mode == "scan_match" and score is not None and matcher is not None \
                and score < matcher.p.min_score:
            stat.summary(WARN, f"scan does not fit the map (score {score:.2f} < "
                               f"{matcher.p.min_score:.2f})")
        elif loc.external:
            stat.summary(OK, "mapping: the SLAM node localizes")
        else:
            stat.summary(OK, f"localized ({loc.mode})")
        stat.add("mode", loc.mode)
        stat.add("corrections", loc.corrections)
        stat.add("match score", "none yet" if score is None else f"{score:.3f}")
        stat.add("odometry age (s)", "none yet" if age is None else f"{age:.2f}")

    def goals(stat: DiagnosticStatusWrapper) -> None:
        status, code, message = ledger.last_outcome
        if status == FAILED:
            stat.summary(WARN, f"last goal failed: {message or f'error {code}'}")
        else:
            stat.summary(OK, "running a goal" if core.motion.active is not None else "idle")
        stat.add("last outcome", {0: "none", 2: "succeeded", 3: "failed", 4: "canceled"}
                 .get(status, str(status)))
        stat.add("error code", code)
        stat.add("error", message)

    up.add("localization", localization)
    up.add("goals", goals)
    return up
