"""The rmw_zenoh bridge: zenros topics and services seen by ROS 2 nodes on rmw_zenoh, and
theirs in the zenros graph, on one Zenoh router (see docs/ros2.md)."""
