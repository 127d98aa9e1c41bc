"""ROS 2 definitions of the nav2_msgs types zenros carries, as Nav2 defines them.

Field names, types and order of ros-navigation/navigation2's ``nav2_msgs`` (comments,
constants and default values left out: a type hash covers none of them), so their RIHS01
hashes are Nav2's own (tests/unit/ros2/test_nav2_hashes.py holds the hashes ROS 2's
generator computes from Nav2's files). Release: Kilted (nav2_msgs 1.4.2), except
NavigateThroughPoses, which is Jazzy's (1.3.13): Kilted's goal wraps the poses in
``nav_msgs/Goals`` where zenros keeps Jazzy's plain ``PoseStamped[] poses``.

zenros's classes may hold more than Nav2's definition (``NavigateToPoseFeedback``'s tracking
errors, ``ComputePathToPoseGoal.viapoints``, ``NavigateThroughPoses``' waypoint statuses; from
Nav2's main branch): CDR carries only the definition's fields, so those stay on the zenros
side; a field Nav2 has and zenros does not (``FollowPath_Result.result``, an empty
structure) is written with its default. docs/ros2.md lists the differences per type.
"""

from __future__ import annotations

__all__ = ["NAV2_ACTIONS", "NAV2_MESSAGES", "NAV2_SERVICES"]

_POSE = "geometry_msgs/PoseStamped"
_DURATION = "builtin_interfaces/Duration"

NAV2_MESSAGES: dict[str, str] = {
    "nav2_msgs/msg/WaypointStatus": f"""
uint8 waypoint_status
uint32 waypoint_index
{_POSE} waypoint_pose
uint16 error_code
string error_msg""",
}

NAV2_SERVICES: dict[str, str] = {
    "nav2_msgs/srv/LoadMap": "string map_url\n---\nnav_msgs/OccupancyGrid map\nuint8 result",
    "nav2_msgs/srv/SaveMap": """
string map_topic
string map_url
string image_format
string map_mode
float32 free_thresh
float32 occupied_thresh
---
bool result""",
    "nav2_msgs/srv/ClearEntireCostmap": "std_msgs/Empty request\n---\nstd_msgs/Empty response",
    "nav2_msgs/srv/ManageLifecycleNodes": "uint8 command\n---\nbool success",
}

_RESULT = "uint16 error_code\nstring error_msg"

NAV2_ACTIONS: dict[str, str] = {
    "nav2_msgs/action/NavigateToPose": f"""
{_POSE} pose
string behavior_tree
---
{_RESULT}
---
{_POSE} current_pose
{_DURATION} navigation_time
{_DURATION} estimated_time_remaining
int16 number_of_recoveries
float32 distance_remaining""",
    # Jazzy's form (see the module docstring)
    "nav2_msgs/action/NavigateThroughPoses": f"""
{_POSE}[] poses
string behavior_tree
---
{_RESULT}
---
{_POSE} current_pose
{_DURATION} navigation_time
{_DURATION} estimated_time_remaining
int16 number_of_recoveries
float32 distance_remaining
int16 number_of_poses_remaining""",
    "nav2_msgs/action/ComputePathToPose": f"""
{_POSE} goal
{_POSE} start
string planner_id
bool use_start
---
nav_msgs/Path path
{_DURATION} planning_time
{_RESULT}
---""",
    "nav2_msgs/action/FollowPath": f"""
nav_msgs/Path path
string controller_id
string goal_checker_id
string progress_checker_id
---
std_msgs/Empty result
{_RESULT}
---
float32 distance_to_goal
float32 speed""",
    "nav2_msgs/action/FollowWaypoints": f"""
uint32 number_of_loops
uint32 goal_index
{_POSE}[] poses
---
WaypointStatus[] missed_waypoints
{_RESULT}
---
uint32 current_waypoint""",
    "nav2_msgs/action/Spin": f"""
float32 target_yaw
{_DURATION} time_allowance
bool disable_collision_checks
---
{_DURATION} total_elapsed_time
{_RESULT}
---
float32 angular_distance_traveled""",
    "nav2_msgs/action/BackUp": f"""
geometry_msgs/Point target
float32 speed
{_DURATION} time_allowance
bool disable_collision_checks
---
{_DURATION} total_elapsed_time
{_RESULT}
---
float32 distance_traveled""",
    "nav2_msgs/action/DockRobot": f"""
bool use_dock_id
string dock_id
{_POSE} dock_pose
string dock_type
float32 max_staging_time
bool navigate_to_staging_pose
---
bool success
uint16 error_code
uint16 num_retries
string error_msg
---
uint16 state
{_DURATION} docking_time
uint16 num_retries""",
    "nav2_msgs/action/UndockRobot": f"""
string dock_type
float32 max_undocking_time
---
bool success
{_RESULT}
---""",
}
# DriveOnHeading has BackUp's fields exactly (Nav2 defines them alike)
NAV2_ACTIONS["nav2_msgs/action/DriveOnHeading"] = NAV2_ACTIONS["nav2_msgs/action/BackUp"]
