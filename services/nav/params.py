"""declare_nav_config: nav's parameters, declared on the node with their defaults, checked,
and built into a `NavConfig` (docs/nav.md lists them)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Protocol

from zenros.errors import InvalidParameterValueError

from .behavior import NavParams
from .controller import ControllerParams
from .core import NavConfig
from .costmap import CostmapParams, ObstacleParams
from .docking import DockParams
from .localizer import MODES
from .planner import PlannerParams

__all__ = ["DEMO_MAP", "declare_nav_config"]

DEMO_MAP = Path(__file__).resolve().parents[2] / "deploy" / "maps" / "office" / "office.yaml"


class _Declares(Protocol):
    def declare_parameter(self, name: str, default: Any, *, description: str = "",
                          read_only: bool = False) -> Any: ...


def declare_nav_config(node: _Declares) -> NavConfig:
    """Declare the parameters and return them as a checked `NavConfig`.

    Raises:
        InvalidParameterValueError: a value out of range (names the parameter).
    """
    def f(name: str, default: float, desc: str = "", *, minimum: float | None = 0.0,
          positive: bool = False) -> float:
        v = node.declare_parameter(name, float(default), description=desc)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                or (positive and v <= 0) or (minimum is not None and v < minimum):
            bound = "> 0" if positive else f">= {minimum}"
            raise InvalidParameterValueError(f"parameter {name!r}: expected a finite number "
                                             f"{bound}, got {v!r}")
        return float(v)

    def b(name: str, default: bool, desc: str = "") -> bool:
        return bool(node.declare_parameter(name, default, description=desc))

    def i(name: str, default: int, desc: str = "") -> int:
        v = node.declare_parameter(name, default, description=desc)
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise InvalidParameterValueError(f"parameter {name!r}: expected an int >= 0, "
                                             f"got {v!r}")
        return v

    robot_radius = f("robot_radius", 0.22, "inscribed radius (m) for costmaps and collisions",
                     positive=True)
    csf = f("cost_scaling_factor", 3.0, "inflation decay", positive=True)
    costmap = CostmapParams(
        robot_radius=robot_radius,
        inflation_radius=f("inflation_radius", 0.7, "inflation radius (m)", positive=True),
        cost_scaling_factor=csf,
        obstacle=ObstacleParams(
            obstacle_max_range=f("obstacle_max_range", 2.5, "scan marking range (m)"),
            raytrace_max_range=f("raytrace_max_range", 3.0, "scan clearing range (m)")))
    planner = PlannerParams(
        cost_weight=f("cost_travel_multiplier", 2.0, "Smac 2D's cost weight"),
        allow_unknown=b("allow_unknown", True, "plan through unknown cells"),
        timeout=f("max_planning_time", 2.0, "seconds per plan (0: no limit)"))
    planner_tolerance = f("planner_tolerance", 0.25, "m: an occupied goal moves to the nearest "
                                                     "free cell this close")
    controller = ControllerParams(
        max_linear_vel=f("max_linear_vel", 0.5, "m/s", positive=True),
        max_angular_vel=f("max_angular_vel", 1.5, "rad/s", positive=True),
        lookahead_dist=f("lookahead_dist", 0.6, "m", positive=True),
        min_lookahead_dist=f("min_lookahead_dist", 0.3, "m", positive=True),
        max_lookahead_dist=f("max_lookahead_dist", 0.9, "m", positive=True),
        lookahead_time=f("lookahead_time", 1.5, "s"),
        use_velocity_scaled_lookahead_dist=b("use_velocity_scaled_lookahead_dist", False),
        use_rotate_to_heading=b("use_rotate_to_heading", True),
        rotate_to_heading_angular_vel=f("rotate_to_heading_angular_vel", 1.0, "rad/s",
                                        positive=True),
        rotate_to_heading_min_angle=f("rotate_to_heading_min_angle", 0.785, "rad"),
        max_linear_accel=f("max_linear_accel", 1.0, "m/s^2", positive=True),
        max_angular_accel=f("max_angular_accel", 3.0, "rad/s^2", positive=True),
        min_approach_linear_velocity=f("min_approach_linear_velocity", 0.05, "m/s"),
        approach_velocity_scaling_dist=f("approach_velocity_scaling_dist", 0.6, "m"),
        regulated_linear_scaling_min_radius=f("regulated_linear_scaling_min_radius", 0.9, "m",
                                              positive=True),
        regulated_linear_scaling_min_speed=f("regulated_linear_scaling_min_speed", 0.25, "m/s"),
        cost_scaling_dist=f("cost_scaling_dist", 0.6, "m"),
        cost_scaling_gain=f("cost_scaling_gain", 1.0),
        inflation_cost_scaling_factor=csf, inscribed_radius=robot_radius,
        xy_goal_tolerance=f("xy_goal_tolerance", 0.15, "m", positive=True),
        yaw_goal_tolerance=f("yaw_goal_tolerance", 0.15, "rad", positive=True))
    controller.check()
    nav = NavParams(
        robot_radius=robot_radius,
        collision_radius=f("collision_radius", 0.2, "m: the body's radius for the scan check",
                           positive=True),
        collision_horizon=f("collision_horizon", 1.0, "s of the commanded arc checked",
                            positive=True),
        replan_period=f("replan_period", 1.0, "s between replans (0: plan once)"),
        blocked_wait=f("blocked_wait", 1.5, "s stopped before a recovery"),
        progress_timeout=f("progress_timeout", 10.0, "s without progress before a recovery",
                           positive=True),
        max_recoveries=i("max_recoveries", 6, "recoveries before a goal fails"),
        plan_retries=i("plan_retries", 1, "failed plans (after clearing) before a goal fails"),
        backup_distance=f("backup_distance", 0.25, "m"),
        spin_angle=f("spin_angle", 1.57, "rad"),
        wait_duration=f("wait_duration", 2.0, "s"),
        navigation_timeout=f("navigation_timeout", 0.0, "s before a goal fails with TIMEOUT "
                                                         "(0: no limit)"))
    dock = DockParams(
        staging_offset=f("staging_x_offset", 0.7, "m in front of the dock", positive=True),
        docking_threshold=f("docking_threshold", 0.05, "m", positive=True),
        wait_charge_timeout=f("wait_charge_timeout", 5.0, "s", positive=True),
        max_retries=i("dock_max_retries", 3),
        use_battery_status=b("use_battery_status", True, "docked = charging starts"))
    mode = str(node.declare_parameter("localization", "ground_truth",
                                      description="ground_truth, odometry or scan_match"))
    if mode not in MODES:
        raise InvalidParameterValueError(f"parameter 'localization': expected one of "
                                         f"{', '.join(MODES)}, got {mode!r}")
    return NavConfig(
        nav=nav, controller=controller, costmap=costmap, planner=planner, dock=dock,
        planner_tolerance=planner_tolerance,
        localization=mode,
        costmap_update_rate=f("costmap_update_rate", 2.0, "obstacle updates per second"),
        local_costmap_size=f("local_costmap_size", 3.0, "m", positive=True),
        scan_match_rate=f("scan_match_rate", 5.0, "scan matches per second (scan_match mode)"),
        scan_match_gain=f("scan_match_gain", 0.5, "fraction of each match's correction "
                                                  "applied"))
