"""Diagnostics as ROS's diagnostic_updater and diagnostic_aggregator (docs/diagnostics.md).

`Updater` runs a node's diagnostic tasks and publishes their statuses on ``/diagnostics``;
`FrequencyStatus` and `TimeStampStatus` are the standard tasks; `DiagnosticStatusWrapper` is
the status a task fills. `Aggregator` (run as ``python -m zenros.services.diagnostics``)
sorts them into a tree by analyzers and publishes it on ``/diagnostics_agg``.
"""

from __future__ import annotations

from .aggregator import Aggregator, GenericAnalyzer, OtherAnalyzer, analyzers_from_params
from .status import ERROR, LEVEL_NAMES, OK, STALE, WARN, DiagnosticStatusWrapper
from .update_functions import (
    FrequencyStatus,
    FrequencyStatusParam,
    TimeStampStatus,
    TimeStampStatusParam,
)
from .updater import CompositeDiagnosticTask, DiagnosticTask, FunctionDiagnosticTask, Updater

__all__ = [
    "ERROR",
    "LEVEL_NAMES",
    "OK",
    "STALE",
    "WARN",
    "Aggregator",
    "CompositeDiagnosticTask",
    "DiagnosticStatusWrapper",
    "DiagnosticTask",
    "FrequencyStatus",
    "FrequencyStatusParam",
    "FunctionDiagnosticTask",
    "GenericAnalyzer",
    "OtherAnalyzer",
    "TimeStampStatus",
    "TimeStampStatusParam",
    "Updater",
    "analyzers_from_params",
]
