"""`NavParameters`: nav's parameters, their only defaults, limits and descriptions (docs/nav.md
lists them), and `nav_config`, which builds the core's `NavConfig` from them."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.errors import InvalidParameterValueError
from zenros.param_config import declare_parameters
from zenros.params import Parameters

from .core import NavConfig
from .costmap import CostmapParams, ObstacleParams
from .localization.localizer import Mode
from .motion.behavior import NavParams
from .motion.controller import ControllerParams
from .motion.docking import DockParams
from .planning import PlannerParams
from .planning.plan import MAX_COST_WEIGHT
from .planning.registry import (
    DEFAULT_PLANNERS,
    DEFAULT_TYPES,
    PlannerSpec,
    check_names,
    plugin_type,
)

__all__ = ["DEMO_MAP", "NavParameters", "nav_config", "planner_specs"]

DEMO_MAP = Path(__file__).resolve().parents[2] / "deploy" / "maps" / "office" / "office.yaml"

Positive = Annotated[float, Meta(gt=0)]
NonNegative = Annotated[float, Meta(ge=0)]
Count = Annotated[int, Meta(ge=0)]


class NavParameters(msgspec.Struct, kw_only=True):
    """Every parameter the nav node declares (``node.declare_parameters(NavParameters)``).

    The values live-changeable today (``localization``, ``auto_charge``,
    ``go_charge_percentage``) follow changes; the others are read at start.
    """

    # maps and rates of the node
    map: Annotated[str, Meta(description="map_server YAML to start with (default: the demo "
                                         "office)")] = ""
    maps_dir: Annotated[str, Meta(description="maps folder (default: $ZENROS_HOME/maps)")] = ""
    building: Annotated[str, Meta(description=(
        "a building file (docs/building.md): its floors' maps, hall points and elevator "
        "connections are put in the map store at start ('' = none)"))] = ""
    controller_frequency: Annotated[Positive, Meta(description="control steps per second")] = 20.0
    pose_publish_rate: Annotated[Positive, Meta(description="robot_pose and map -> odom per "
                                                            "second")] = 10.0
    global_costmap_publish_rate: Annotated[Positive, Meta(description="per second")] = 1.0
    local_costmap_publish_rate: Annotated[Positive, Meta(description="per second")] = 2.0
    auto_charge: Annotated[bool, Meta(description="dock when the battery runs low")] = False
    go_charge_percentage: Annotated[float, Meta(
        ge=0, le=1, description="battery fraction that sends it to dock")] = 0.2
    # schedule mode (docs/fleet.md, "Traffic schedule")
    schedule_mode: Annotated[bool, Meta(description=(
        "start in schedule mode: drive only where the schedule manager grants "
        "(set_schedule_mode turns it on and off)"))] = False
    schedule_server: Annotated[str, Meta(
        pattern=r"^[A-Za-z0-9_]{1,64}$",
        description="the schedule server whose traffic schedule schedule mode follows")] = "local"
    schedule_lease: Annotated[Positive, Meta(description=(
        "seconds the manager holds the robot's reservations without a renewal"))] = 3.0
    # costmaps
    robot_radius: Annotated[Positive, Meta(
        description="inscribed radius (m) for costmaps and collisions")] = 0.22
    inflation_radius: Annotated[Positive, Meta(description="inflation radius (m)")] = 0.7
    cost_scaling_factor: Annotated[Positive, Meta(description="inflation decay")] = 3.0
    obstacle_max_range: Annotated[NonNegative, Meta(description="scan marking range (m)")] = 2.5
    raytrace_max_range: Annotated[NonNegative, Meta(description="scan clearing range (m)")] = 3.0
    costmap_update_rate: Annotated[NonNegative, Meta(
        description="obstacle updates per second")] = 2.0
    local_costmap_size: Annotated[Positive, Meta(description="m")] = 3.0
    # planner
    planner_plugins: Annotated[list[str], Meta(
        description="planner ids, the default first; each one's type is <id>.plugin "
                    "(Nav2's planner_plugins)")] = msgspec.field(
        default_factory=lambda: list(DEFAULT_PLANNERS))
    cost_travel_multiplier: Annotated[float, Meta(
        ge=0, le=MAX_COST_WEIGHT, description="Smac 2D's cost weight")] = 2.0
    allow_unknown: Annotated[bool, Meta(description="plan through unknown cells")] = True
    max_planning_time: Annotated[NonNegative, Meta(
        description="seconds per plan (0: no limit)")] = 2.0
    planner_tolerance: Annotated[NonNegative, Meta(
        description="m: an occupied goal moves to the nearest free cell this close")] = 0.25
    # controller (Regulated Pure Pursuit) and goal checker
    max_linear_vel: Annotated[Positive, Meta(description="m/s")] = 0.5
    max_angular_vel: Annotated[Positive, Meta(description="rad/s")] = 1.5
    lookahead_dist: Annotated[Positive, Meta(description="m")] = 0.6
    min_lookahead_dist: Annotated[Positive, Meta(description="m")] = 0.3
    max_lookahead_dist: Annotated[Positive, Meta(description="m")] = 0.9
    lookahead_time: Annotated[NonNegative, Meta(description="s")] = 1.5
    use_velocity_scaled_lookahead_dist: bool = False
    use_rotate_to_heading: bool = True
    rotate_to_heading_angular_vel: Annotated[Positive, Meta(description="rad/s")] = 1.0
    rotate_to_heading_min_angle: Annotated[NonNegative, Meta(description="rad")] = 0.785
    max_linear_accel: Annotated[Positive, Meta(description="m/s^2")] = 1.0
    max_angular_accel: Annotated[Positive, Meta(description="rad/s^2")] = 3.0
    min_approach_linear_velocity: Annotated[NonNegative, Meta(description="m/s")] = 0.05
    approach_velocity_scaling_dist: Annotated[NonNegative, Meta(description="m")] = 0.6
    regulated_linear_scaling_min_radius: Annotated[Positive, Meta(description="m")] = 0.9
    regulated_linear_scaling_min_speed: Annotated[NonNegative, Meta(description="m/s")] = 0.25
    cost_scaling_dist: Annotated[NonNegative, Meta(description="m")] = 0.6
    cost_scaling_gain: NonNegative = 1.0
    xy_goal_tolerance: Annotated[Positive, Meta(description="m")] = 0.15
    yaw_goal_tolerance: Annotated[Positive, Meta(description="rad")] = 0.15
    # behaviour: collisions, replanning, recoveries
    collision_radius: Annotated[Positive, Meta(
        description="m: the body's radius for the scan check")] = 0.2
    collision_horizon: Annotated[Positive, Meta(
        description="s of the commanded arc checked")] = 1.0
    replan_period: Annotated[NonNegative, Meta(
        description="s between replans (0: plan once)")] = 1.0
    blocked_wait: Annotated[NonNegative, Meta(description="s stopped before a recovery")] = 1.5
    progress_timeout: Annotated[Positive, Meta(
        description="s without progress before a recovery")] = 10.0
    max_recoveries: Annotated[Count, Meta(description="recoveries before a goal fails")] = 6
    plan_retries: Annotated[Count, Meta(
        description="failed plans (after clearing) before a goal fails")] = 1
    backup_distance: Annotated[NonNegative, Meta(description="m")] = 0.25
    spin_angle: Annotated[NonNegative, Meta(description="rad")] = 1.57
    wait_duration: Annotated[NonNegative, Meta(description="s")] = 2.0
    navigation_timeout: Annotated[NonNegative, Meta(
        description="s before a goal fails with TIMEOUT (0: no limit)")] = 0.0
    # docking
    staging_x_offset: Annotated[Positive, Meta(description="m in front of the dock")] = 0.7
    docking_threshold: Annotated[Positive, Meta(description="m")] = 0.05
    wait_charge_timeout: Annotated[Positive, Meta(description="s")] = 5.0
    dock_max_retries: Count = 3
    use_battery_status: Annotated[bool, Meta(description="docked = charging starts")] = True
    # localisation
    localization: Annotated[Mode, Meta(description="where the robot pose comes from")] = (
        "ground_truth")
    scan_match_rate: Annotated[NonNegative, Meta(
        description="scan matches per second (scan_match mode)")] = 5.0
    scan_match_gain: Annotated[NonNegative, Meta(
        description="fraction of each match's correction applied")] = 0.5
    save_map_timeout: Annotated[NonNegative, Meta(
        description="map_saver/save_map: seconds to wait for a grid on map_topic")] = 2.0


def planner_specs(names: list[str], parameters: Parameters | None = None
                  ) -> tuple[PlannerSpec, ...]:
    """The planners ``planner_plugins`` names, with each one's ``<id>.plugin`` and its own
    parameters (``<id>.<field>``) declared read-only on ``parameters`` (None: defaults).

    Raises:
        InvalidParameterValueError: no id, a repeated one, an unknown plugin type (the
            message lists the known ones), a plugin parameter out of its limits.
    """
    try:
        check_names(names)
        specs = []
        for name in names:
            default = DEFAULT_TYPES.get(name, "")
            plugin = default if parameters is None else parameters.declare(
                f"{name}.plugin", default, read_only=True,
                description=f"the type of planner {name} (one of nav's planner plugins)")
            kind = plugin_type(name, plugin)
            params = kind.Parameters() if parameters is None else declare_parameters(
                parameters, kind.Parameters, read_only=True, prefix=f"{name}.")
            specs.append(PlannerSpec(name, plugin, params))
    except ValueError as exc:
        raise InvalidParameterValueError(str(exc)) from None
    return tuple(specs)


def nav_config(p: NavParameters, parameters: Parameters | None = None) -> NavConfig:
    """The core's configuration from the parameters; with ``parameters`` (the node's), the
    planners' own parameters are declared there (`planner_specs`).

    Raises:
        ValueError: a combination the controller refuses (`ControllerParams.check`).
        InvalidParameterValueError: a planner that cannot be built (`planner_specs`).
    """
    controller = ControllerParams(
        max_linear_vel=p.max_linear_vel, max_angular_vel=p.max_angular_vel,
        lookahead_dist=p.lookahead_dist, min_lookahead_dist=p.min_lookahead_dist,
        max_lookahead_dist=p.max_lookahead_dist, lookahead_time=p.lookahead_time,
        use_velocity_scaled_lookahead_dist=p.use_velocity_scaled_lookahead_dist,
        use_rotate_to_heading=p.use_rotate_to_heading,
        rotate_to_heading_angular_vel=p.rotate_to_heading_angular_vel,
        rotate_to_heading_min_angle=p.rotate_to_heading_min_angle,
        max_linear_accel=p.max_linear_accel, max_angular_accel=p.max_angular_accel,
        min_approach_linear_velocity=p.min_approach_linear_velocity,
        approach_velocity_scaling_dist=p.approach_velocity_scaling_dist,
        regulated_linear_scaling_min_radius=p.regulated_linear_scaling_min_radius,
        regulated_linear_scaling_min_speed=p.regulated_linear_scaling_min_speed,
        cost_scaling_dist=p.cost_scaling_dist, cost_scaling_gain=p.cost_scaling_gain,
        inflation_cost_scaling_factor=p.cost_scaling_factor, inscribed_radius=p.robot_radius,
        xy_goal_tolerance=p.xy_goal_tolerance, yaw_goal_tolerance=p.yaw_goal_tolerance)
    controller.check()
    return NavConfig(
        nav=NavParams(
            robot_radius=p.robot_radius, collision_radius=p.collision_radius,
            collision_horizon=p.collision_horizon, replan_period=p.replan_period,
            blocked_wait=p.blocked_wait, progress_timeout=p.progress_timeout,
            max_recoveries=p.max_recoveries, plan_retries=p.plan_retries,
            backup_distance=p.backup_distance, spin_angle=p.spin_angle,
            wait_duration=p.wait_duration, navigation_timeout=p.navigation_timeout),
        controller=controller,
        costmap=CostmapParams(
            robot_radius=p.robot_radius, inflation_radius=p.inflation_radius,
            cost_scaling_factor=p.cost_scaling_factor,
            obstacle=ObstacleParams(obstacle_max_range=p.obstacle_max_range,
                                    raytrace_max_range=p.raytrace_max_range)),
        planner=PlannerParams(cost_weight=p.cost_travel_multiplier,
                              allow_unknown=p.allow_unknown, timeout=p.max_planning_time),
        dock=DockParams(
            staging_offset=p.staging_x_offset, docking_threshold=p.docking_threshold,
            wait_charge_timeout=p.wait_charge_timeout, max_retries=p.dock_max_retries,
            use_battery_status=p.use_battery_status),
        planners=planner_specs(p.planner_plugins, parameters),
        planner_tolerance=p.planner_tolerance, localization=p.localization,
        costmap_update_rate=p.costmap_update_rate, local_costmap_size=p.local_costmap_size,
        scan_match_rate=p.scan_match_rate, scan_match_gain=p.scan_match_gain)
