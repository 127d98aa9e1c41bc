"""Behavior: a tick-driven piece of robot motion (navigate, follow a path, dock, undock).

The control loop calls `tick(sense)` every period with what the robot senses and sends
the returned (v, ω) on ``cmd_vel``. A behaviour ends by calling `finish` (success or an
error code); `halt` stops it from outside (cancel, preemption). Behaviours never block.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
from zenros.se2 import Pose2

from ..planning.global_planner import PlanWorker

__all__ = ["Behavior", "NavParams", "NavTools", "Sense"]


@dataclass
class Sense:
    """What the robot knows at one tick (``now`` in seconds of the node's clock)."""

    now: float
    dt: float
    pose: Pose2 | None
    speed: tuple[float, float] = (0.0, 0.0)
    obstacles: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    """Scan points in ``base_link`` (x forward, y left), (M, 2)."""
    battery: float | None = None
    charging: bool = False
    docked: bool = False


@dataclass(frozen=True)
class NavParams:
    """Navigation parameters besides the controller's (see docs/nav.md)."""

    robot_radius: float = 0.22
    collision_radius: float = 0.2
    """The body's radius for the scan check (the costmaps' robot_radius is padded)."""
    collision_horizon: float = 1.0
    replan_period: float = 1.0
    blocked_wait: float = 1.5
    progress_timeout: float = 10.0
    progress_distance: float = 0.3
    max_recoveries: int = 6
    plan_retries: int = 1
    backup_distance: float = 0.25
    backup_speed: float = 0.1
    spin_angle: float = 1.57
    spin_speed: float = 1.0
    wait_duration: float = 2.0
    localization_timeout: float = 5.0
    navigation_timeout: float = 0.0
    """Seconds after which a navigation goal fails with TIMEOUT (0: no limit)."""


class NavTools(Protocol):
    """What behaviours use of the node: the planner and the global costmap."""

    worker: PlanWorker

    def cost_at(self, x: float, y: float) -> int: ...

    def keepout_hit(self, points: np.ndarray) -> bool: ...

    def clear_obstacles(self) -> None: ...

    def on_plan(self, xy: np.ndarray) -> None: ...


class Behavior:
    """Base: completion state shared with the action thread that waits on it."""

    name = "behavior"

    def __init__(self) -> None:
        self.done = threading.Event()
        self.succeeded = False
        self.error_code = 0
        self.error_msg = ""
        self.started_at: float | None = None
        self.halted = False

    def tick(self, sense: Sense) -> tuple[float, float]:
        raise NotImplementedError

    def step(self, sense: Sense) -> tuple[float, float]:
        """`tick` unless finished; stamps the start time."""
        if self.started_at is None:
            self.started_at = sense.now
        if self.done.is_set():
            return 0.0, 0.0
        return self.tick(sense)

    def finish(self, ok: bool, code: int = 0, msg: str = "") -> tuple[float, float]:
        if not self.done.is_set():
            self.succeeded, self.error_code, self.error_msg = ok, code, msg
            self.done.set()
        return 0.0, 0.0

    def halt(self, reason: str) -> None:
        """Stop from outside; the behaviour ends unsuccessfully with ``reason``."""
        self.halted = True
        self.finish(False, 0, reason)
