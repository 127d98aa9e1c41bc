"""`DiagnosticStatusWrapper`: a DiagnosticStatus with diagnostic_updater's helpers."""

from __future__ import annotations

from typing import Any, TypeVar

from ..msgs.diagnostic_msgs import DiagnosticStatus, KeyValue

__all__ = ["ERROR", "LEVEL_NAMES", "OK", "STALE", "WARN", "DiagnosticStatusWrapper", "plain"]

OK, WARN, ERROR, STALE = (DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR,
                          DiagnosticStatus.STALE)
LEVEL_NAMES = {OK: "OK", WARN: "Warning", ERROR: "Error", STALE: "Stale"}  # the aggregator's

V = TypeVar("V")


class DiagnosticStatusWrapper(DiagnosticStatus):
    """What a task fills: ``summary(level, message)`` (or ``summary(status)``),
    ``merge_summary`` (the worse level wins; messages of the same kind, OK or not, are
    joined with "; "), ``clear_summary()``, ``add(key, value)``. rclpy's camelCase names
    (``mergeSummary``, ``clearSummary``) work too."""

    def summary(self, *args: Any) -> None:
        level, message = _level_message(args)
        self.level, self.message = level, message

    def clear_summary(self) -> None:
        self.summary(OK, "")

    def merge_summary(self, *args: Any) -> None:
        level, message = _level_message(args)
        if (level > OK) == (self.level > OK):
            if self.message:
                self.message += "; "
            self.message += message
        elif level > self.level:
            self.message = message
        self.level = max(self.level, level)

    def add(self, key: str, value: V) -> V:
        """Add ``key: str(value)`` to the values; returns ``value``."""
        self.values.append(KeyValue(key=str(key), value=str(value)))
        return value

    clearSummary = clear_summary
    mergeSummary = merge_summary


def _level_message(args: tuple[Any, ...]) -> tuple[int, str]:
    if len(args) == 1 and isinstance(args[0], DiagnosticStatus):
        return args[0].level, args[0].message
    if len(args) == 2:
        level, message = args
        if isinstance(level, bytes):  # rclpy's byte fields
            level = level[0]
        if int(level) not in LEVEL_NAMES:
            raise ValueError(f"diagnostic level {level!r}: one of OK 0, WARN 1, ERROR 2, STALE 3")
        return int(level), str(message)
    raise TypeError("summary takes (level, message) or (status)")


def plain(s: DiagnosticStatus) -> DiagnosticStatus:
    """The same status as a plain DiagnosticStatus (what goes on the wire)."""
    return DiagnosticStatus(level=s.level, name=s.name, message=s.message,
                            hardware_id=s.hardware_id, values=list(s.values))
