"""The services a replay can run, by the name ``zenros replay --nodes`` takes."""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Any

from ..errors import ConfigError

__all__ = ["REPLAYABLE", "Replayable", "replayable"]


@dataclass(frozen=True)
class Replayable:
    """A node class (``module:Class``) and what the wall-clock check may ignore in it: path
    fragments of callers, each with the reason its reads reach no output."""

    target: str
    exempt: dict[str, str] = field(default_factory=dict)

    def load(self) -> Any:
        module, _, name = self.target.partition(":")
        return getattr(importlib.import_module(module), name)


REPLAYABLE: dict[str, Replayable] = {
    "nav": Replayable("zenros.services.nav.node:NavNode", {
        "/nav/planning/": "the planner measures its planning time for the ComputePathToPose "
                          "result (no topic carries it); its budget is off in a replay",
    }),
    "slam": Replayable("zenros.services.slam.node:SlamNode"),
}


def replayable(name: str) -> Replayable:
    """The service ``name``; `ConfigError` naming the known ones."""
    try:
        return REPLAYABLE[name]
    except KeyError:
        raise ConfigError(f"no replayable service {name!r}; known: "
                          f"{', '.join(sorted(REPLAYABLE))}") from None
