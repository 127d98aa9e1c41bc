"""Deterministic replay: nodes composed in one process on a clock driven by a bag, with every
message and timer dispatched in a defined order (docs/replay.md)."""

from .bagrun import ReplayResult, replay_bag
from .clock import ReplayClock
from .compare import Difference, compare_bags
from .context import ReplayContext
from .executor import DeterministicExecutor
from .run import DeterministicRun
from .scenario import Scenario, ScenarioFailed
from .walltime import WallClockCheck

__all__ = ["DeterministicExecutor", "DeterministicRun", "Difference", "ReplayClock",
           "ReplayContext", "ReplayResult", "Scenario", "ScenarioFailed", "WallClockCheck",
           "compare_bags", "replay_bag"]
