"""The ROS 2 domain of the environment (``ROS_DOMAIN_ID``), the bridges' default domain."""

from __future__ import annotations

import os

__all__ = ["env_domain_id"]


def env_domain_id() -> int:
    """``ROS_DOMAIN_ID`` of the environment, or 0 when it is unset or empty."""
    return int(os.environ.get("ROS_DOMAIN_ID", "0") or 0)
