"""The standard message, service and action types; importing registers them all."""

from . import (
    builtin_interfaces,
    example_interfaces,
    geometry_msgs,
    nav_msgs,
    rcl_interfaces,
    rosgraph_msgs,
    sensor_msgs,
    std_msgs,
    std_srvs,
    tf2_msgs,
    tf_srvs,
)

__all__ = [
    "builtin_interfaces",
    "example_interfaces",
    "geometry_msgs",
    "nav_msgs",
    "rcl_interfaces",
    "rosgraph_msgs",
    "sensor_msgs",
    "std_msgs",
    "std_srvs",
    "tf2_msgs",
    "tf_srvs",
]
