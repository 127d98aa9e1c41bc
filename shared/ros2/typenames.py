"""ROS 2 type names in their three spellings.

zenros ``geometry_msgs/Twist``, ROS 2 ``geometry_msgs/msg/Twist`` and DDS
``geometry_msgs::msg::dds_::Twist_``; services' parts are ``pkg/srv/Name_Request`` and
``pkg::srv::dds_::Name_Request_``, actions' ``pkg/action/Name_SendGoal_Request`` and so on.
"""

from __future__ import annotations

import re

from ..errors import UnknownTypeError
from ..message import normalize_type_name

__all__ = ["dds_to_ros", "ros_to_dds", "ros_to_zenros", "split_ros_name", "zenros_to_ros"]

_ROS_RE = re.compile(r"^([A-Za-z][A-Za-z0-9_]*)/(msg|srv|action)/([A-Za-z][A-Za-z0-9_]*)$")
_DDS_RE = re.compile(r"^([A-Za-z][A-Za-z0-9_]*)::(msg|srv|action)::dds_::([A-Za-z][A-Za-z0-9_]*)_$")


def split_ros_name(name: str) -> tuple[str, str, str]:
    """``pkg/msg/Name`` -> (pkg, msg, Name); raises `UnknownTypeError` on another form."""
    m = _ROS_RE.match(name)
    if not m:
        raise UnknownTypeError(f"not a ROS 2 type name (pkg/msg|srv|action/Name): {name!r}")
    return m[1], m[2], m[3]


def ros_to_dds(name: str) -> str:
    """``geometry_msgs/msg/Twist`` -> ``geometry_msgs::msg::dds_::Twist_``."""
    pkg, kind, short = split_ros_name(name)
    return f"{pkg}::{kind}::dds_::{short}_"


def dds_to_ros(name: str) -> str:
    """``geometry_msgs::msg::dds_::Twist_`` -> ``geometry_msgs/msg/Twist``."""
    m = _DDS_RE.match(name)
    if not m:
        raise UnknownTypeError(f"not a DDS type name of a ROS 2 type: {name!r}")
    return f"{m[1]}/{m[2]}/{m[3]}"


def zenros_to_ros(name: str, kind: str = "msg") -> str:
    """zenros ``geometry_msgs/Twist`` (or already ``pkg/msg/Name``) -> ``geometry_msgs/msg/Twist``;
    ``kind`` is ``srv`` or ``action`` for a service or action type name."""
    if _ROS_RE.match(name):
        return name
    pkg, _, short = normalize_type_name(name).partition("/")
    if not pkg or not short or "/" in short:
        raise UnknownTypeError(f"not a type name: {name!r}")
    return f"{pkg}/{kind}/{short}"


def ros_to_zenros(name: str) -> str:
    """``geometry_msgs/msg/Twist`` -> ``geometry_msgs/Twist`` (zenros's registry key)."""
    pkg, _, short = split_ros_name(name)
    return f"{pkg}/{short}"
