"""``python -m zenros.services.gateway.ros2``: the ROS 2 DDS bridge on its own."""

from zenros import run

from .bridge import Ros2DdsBridge

run(Ros2DdsBridge)
