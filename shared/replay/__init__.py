"""Deterministic replay: nodes composed in one process on a clock driven by a bag, with every
message and timer dispatched in a defined order (docs/replay.md)."""

from .clock import ReplayClock
from .context import ReplayContext
from .executor import DeterministicExecutor
from .run import DeterministicRun
from .walltime import WallClockCheck

__all__ = ["DeterministicExecutor", "DeterministicRun", "ReplayClock", "ReplayContext",
           "WallClockCheck"]
