"""The ROS 2 DDS bridge: ROS 2 topics on a DDS domain mirrored into the zenros graph under
their ROS names, and zenros topics into ROS 2 (see docs/ros2.md, "DDS")."""
