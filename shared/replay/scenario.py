"""Scenario tests from bags: a short input bag and the output a replay of it must give.

    from zenros.replay.scenario import Scenario

    def test_goal_around_obstacle(tmp_path):
        Scenario("tests/scenarios/goal_around_obstacle.in.mcap",
                 "tests/scenarios/goal_around_obstacle.expected.mcap",
                 nodes=["nav"], params={"nav": {"map": "..."}}).check(tmp_path)

`Scenario.check` replays the input into the services, compares the output with the
expected bag message by message, and fails with the first difference (topic, time, field,
both values) and the command that rewrites the expected bag when the change is wanted.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .bagrun import DEFAULT_EXCLUDE, ReplayResult, replay_bag
from .compare import compare_bags

__all__ = ["Scenario", "ScenarioFailed"]


class ScenarioFailed(AssertionError):
    """A replay whose output is not the expected one (or that read the wall clock)."""


@dataclass
class Scenario:
    """An input bag, the expected output bag, the services and their parameters."""

    input: str | Path
    expected: str | Path
    nodes: list[str]
    params: dict[str, dict[str, Any]] = field(default_factory=dict)
    exclude: str = DEFAULT_EXCLUDE
    strict: bool = True
    """Fail also when a node read the wall clock inside a callback (`WallClockCheck`)."""

    def replay(self, output: Path) -> ReplayResult:
        return replay_bag(self.input, self.nodes, output, params=self.params,
                          exclude=self.exclude)

    def check(self, workdir: Path) -> ReplayResult:
        """Replay into ``workdir/<input stem>.out.mcap`` and compare with the expected bag.

        Raises:
            ScenarioFailed: the first difference, or the wall-clock reads (``strict``).
        """
        out = Path(workdir) / f"{Path(self.input).name.split('.')[0]}.out.mcap"
        res = self.replay(out)
        if self.strict and res.wall_reads:
            where = "; ".join(f"{fn}() at {file}:{line}" for fn, file, line in res.wall_reads)
            raise ScenarioFailed(f"the replay read the wall clock inside callbacks: {where}")
        diff = compare_bags(Path(self.expected), out)
        if diff is not None:
            raise ScenarioFailed(
                f"{self.input}: the replay's output differs from {self.expected}: {diff} "
                f"(left: expected, right: this replay, kept at {out}). If the change is "
                "wanted, rewrite the expected bags (tests/scenarios/make_bags.py)")
        return res
