"""The standard message, service and action types; importing registers them all."""

from . import (
    builtin_interfaces,
    example_interfaces,
    galileo_msgs,
    geometry_msgs,
    nav2_msgs,
    nav_msgs,
    rcl_interfaces,
    rosgraph_msgs,
    sensor_msgs,
    slam_toolbox,
    std_msgs,
    std_srvs,
    tf2_msgs,
    tf_srvs,
    zenros_msgs,
)

__all__ = [
    "builtin_interfaces",
    "example_interfaces",
    "galileo_msgs",
    "geometry_msgs",
    "nav2_msgs",
    "nav_msgs",
    "rcl_interfaces",
    "rosgraph_msgs",
    "sensor_msgs",
    "slam_toolbox",
    "std_msgs",
    "std_srvs",
    "tf2_msgs",
    "tf_srvs",
    "zenros_msgs",
]
