"""`DdsBridgeParameters`: the ROS 2 DDS bridge's parameters, their only defaults and limits."""

from __future__ import annotations

from typing import Annotated

from msgspec import Meta
from zenros.ros2.domain import BridgeScope

__all__ = ["DdsBridgeParameters"]


class DdsBridgeParameters(BridgeScope, kw_only=True):
    """The DDS bridge's parameters (docs/ros2.md), read-only: read once, at start."""

    # every node's six parameter services and its type description service too: bridging
    # them (from every rclpy node, once zenros knew their types) slowed the DDS discovery of
    # a test's own service past its first call's 5 s; give deny:='/rosout|/parameter_events'
    # to bridge them
    deny: Annotated[str, Meta(
        description="regex on ROS names never bridged (wins over allow)")] = \
        "/rosout|/parameter_events|.*/(list_parameters|describe_parameters|" \
        "get_parameter_types|get_parameters|set_parameters|set_parameters_atomically|" \
        "get_type_description)"
    depth: Annotated[int, Meta(ge=1, description="keep-last depth of topics from DDS")] = 10
    service_timeout: Annotated[float, Meta(
        gt=0, description="seconds a ROS 2 service has to reply")] = 5.0
    result_timeout: Annotated[float, Meta(
        gt=0, description="seconds one result request of a ROS 2 action waits (a zenros "
                          "client then asks again)")] = 60.0
    types: Annotated[str, Meta(
        description="Python modules of your own to import first, comma-separated: the types "
                    "they define are bridged too (the types zenros ships load by name)")] = ""
