"""`RmwZenohParameters`: the rmw_zenoh bridge's parameters, their only defaults and limits."""

from __future__ import annotations

from typing import Annotated

from msgspec import Meta
from zenros.ros2.domain import BridgeScope

__all__ = ["RmwZenohParameters"]


class RmwZenohParameters(BridgeScope, kw_only=True):
    """The bridge's parameters (docs/ros2.md); read once, at start."""

    services: Annotated[bool, Meta(description="bridge services both ways")] = True
    actions: Annotated[bool, Meta(description="bridge actions both ways")] = True
    mirror_graph: Annotated[bool, Meta(
        description="mirror each side's graph (liveliness tokens) on the other")] = True
    call_timeout: Annotated[float, Meta(
        gt=0, description="seconds a bridged service call waits for its reply")] = 10.0
    result_timeout: Annotated[float, Meta(
        gt=0, description="seconds a bridged action's get_result waits")] = 3600.0
