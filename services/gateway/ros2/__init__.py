"""The ROS 2 DDS bridge: ROS 2 topics on a DDS domain mirrored into the zenros graph under
their ROS names, and zenros topics into ROS 2 (see docs/ros2.md, "DDS")."""

import importlib.util

if importlib.util.find_spec("cyclonedds") is None:  # the optional extra is not installed
    raise ModuleNotFoundError(
        f"{__name__} needs cyclonedds, the extra zenros[ros2]: pip install 'zenros[ros2]'",
        name="cyclonedds")
