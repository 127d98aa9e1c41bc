"""`SlamParameters`: the mapping node's parameters, with slam_toolbox's names and their only
defaults (docs/mapping.md lists them)."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta

__all__ = ["SlamParameters"]

Positive = Annotated[float, Meta(gt=0)]
NonNegative = Annotated[float, Meta(ge=0)]


class SlamParameters(msgspec.Struct, kw_only=True, frozen=True):
    """Everything the mapper and the node read; names as slam_toolbox's where it has one."""

    graph_dir: Annotated[str, Meta(
        description="where pose graphs are saved (default: $ZENROS_HOME/slam)")] = ""
    maps_dir: Annotated[str, Meta(
        description="nav's maps folder, for extending a map with no pose graph (default: "
                    "$ZENROS_HOME/maps)")] = ""
    # frames and topics
    map_frame: str = "map"
    odom_frame: str = "odom"
    base_frame: str = "base_link"
    laser_frame: Annotated[str, Meta(description="the scan's frame; its base_frame -> "
                                                 "laser_frame on /tf_static places it")] = "laser"
    laser_x: Annotated[float, Meta(description="laser on the base (m), until /tf_static "
                                               "says otherwise")] = 0.1
    laser_y: float = 0.0
    laser_yaw: float = 0.0
    # grid
    resolution: Annotated[Positive, Meta(description="map cell size (m)")] = 0.05
    max_laser_range: Annotated[Positive, Meta(
        description="returns beyond this are not used (m)")] = 20.0
    max_clear_range: Annotated[Positive, Meta(
        description="how far a beam with no return clears (m)")] = 6.0
    hit_probability: Annotated[float, Meta(gt=0.5, lt=1)] = 0.7
    miss_probability: Annotated[float, Meta(gt=0, lt=0.5)] = 0.4
    clamp_min: Annotated[float, Meta(gt=0, lt=0.5)] = 0.12
    clamp_max: Annotated[float, Meta(gt=0.5, lt=1)] = 0.97
    # publishing
    map_update_interval: Annotated[Positive, Meta(description="s between map rebuilds")] = 5.0
    transform_publish_period: Annotated[NonNegative, Meta(
        description="s between map -> odom sends (0: off)")] = 0.05
    transform_timeout: Annotated[NonNegative, Meta(
        description="map -> odom is stamped this far past the scan (s)")] = 0.2
    start_mapping: Annotated[bool, Meta(description=(
        "begin a mapping run (a new map) as soon as active, without asking nav to hand over "
        "its map: for a replay of slam alone (docs/replay.md)"))] = False
    scan_queue_size: Annotated[int, Meta(
        ge=1, description="scans that may wait for the mapper; past it the oldest is "
                          "skipped (and the state says so)")] = 100
    # scan gating (Karto HasMovedEnough)
    minimum_travel_distance: Annotated[NonNegative, Meta(description="m")] = 0.5
    minimum_travel_heading: Annotated[NonNegative, Meta(description="rad")] = 0.5
    # sequential matching against the running buffer
    scan_buffer_size: Annotated[int, Meta(ge=1)] = 10
    scan_buffer_maximum_scan_distance: Annotated[Positive, Meta(description="m")] = 10.0
    correlation_search_space_dimension: Annotated[Positive, Meta(
        description="m: the window's side (±half)")] = 0.4
    correlation_search_space_smear_deviation: Annotated[Positive, Meta(
        description="m: σ of the smeared reference points")] = 0.05
    coarse_search_angle_offset: Annotated[Positive, Meta(description="rad (±)")] = 0.1
    coarse_angle_resolution: Annotated[Positive, Meta(description="rad")] = 0.02
    fine_search_angle_offset: Annotated[Positive, Meta(
        description="rad: the fine angle step (Karto's name)")] = 0.004
    distance_variance_penalty: Annotated[Positive, Meta()] = 0.5
    angle_variance_penalty: Annotated[Positive, Meta()] = 1.0
    minimum_distance_penalty: Annotated[NonNegative, Meta()] = 0.5
    minimum_angle_penalty: Annotated[NonNegative, Meta()] = 0.9
    link_match_minimum_response_fine: Annotated[NonNegative, Meta(
        description="below this a scan is placed by odometry alone")] = 0.1
    match_points: Annotated[int, Meta(ge=10, description="scan points used to match (twice as many refine it)")] = 120
    # odometry, fused with each match by their covariances
    odom_translation_sigma: Annotated[NonNegative, Meta(
        description="odometry's position error per metre driven (m/m)")] = 0.05
    odom_rotation_sigma: Annotated[NonNegative, Meta(
        description="odometry's heading error per radian turned (rad/rad)")] = 0.05
    odom_drift_sigma: Annotated[NonNegative, Meta(
        description="odometry's heading error per metre driven (rad/m)")] = 0.01
    # loop closure
    do_loop_closing: bool = True
    loop_search_maximum_distance: Annotated[Positive, Meta(description="m")] = 3.0
    loop_match_minimum_chain_size: Annotated[int, Meta(ge=1)] = 10
    loop_search_space_dimension: Annotated[Positive, Meta(
        description="m: the loop window's side (±half)")] = 4.0
    loop_search_angle_offset: Annotated[Positive, Meta(description="rad (±)")] = 0.349
    loop_match_minimum_response_coarse: Annotated[NonNegative, Meta()] = 0.35
    loop_match_minimum_response_fine: Annotated[NonNegative, Meta()] = 0.45
    loop_match_maximum_variance_coarse: Annotated[Positive, Meta(
        description="m²: a peak this spread (a corridor's) is ambiguous")] = 0.04
    loop_exclude_distance: Annotated[Positive, Meta(
        description="m of travel: nodes this recent are the running chain, not a loop")] = 10.0
    loop_attempt_every: Annotated[int, Meta(ge=1, description="nodes between attempts")] = 2
    # optimiser
    optimizer_iterations: Annotated[int, Meta(ge=1)] = 20
    loop_huber_scale: Annotated[Positive, Meta(description="Huber k on loop edges (σ)")] = 3.0
