"""`RmwZenohParameters`: the rmw_zenoh bridge's parameters, their only defaults and limits."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.ros2.domain import env_domain_id

__all__ = ["RmwZenohParameters"]


class RmwZenohParameters(msgspec.Struct, kw_only=True):
    """The bridge's parameters (docs/ros2.md); read once, at start."""

    domain_id: Annotated[int, Meta(
        ge=0, description="ROS 2 domain (default ROS_DOMAIN_ID, else 0)")] = msgspec.field(
        default_factory=env_domain_id)
    allow: Annotated[str, Meta(description="regex on names to bridge")] = ".*"
    deny: Annotated[str, Meta(
        description="regex on names never bridged (wins over allow; empty: none)")] = ""
    services: Annotated[bool, Meta(description="bridge services both ways")] = True
    actions: Annotated[bool, Meta(description="bridge actions both ways")] = True
    mirror_graph: Annotated[bool, Meta(
        description="mirror each side's graph (liveliness tokens) on the other")] = True
    call_timeout: Annotated[float, Meta(
        gt=0, description="seconds a bridged service call waits for its reply")] = 10.0
    result_timeout: Annotated[float, Meta(
        gt=0, description="seconds a bridged action's get_result waits")] = 3600.0
