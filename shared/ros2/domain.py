"""The ROS 2 domain of the environment (``ROS_DOMAIN_ID``), `BridgeScope`: the parameters both
ROS 2 bridges start from (which domain, which names), and `NameFilter` for those names."""

from __future__ import annotations

import os
import re
from typing import Annotated

import msgspec
from msgspec import Meta

__all__ = ["BridgeScope", "NameFilter", "env_domain_id"]


def env_domain_id() -> int:
    """``ROS_DOMAIN_ID`` of the environment, or 0 when it is unset or empty."""
    return int(os.environ.get("ROS_DOMAIN_ID", "0") or 0)


class BridgeScope(msgspec.Struct, kw_only=True):
    """A bridge's domain and the names it bridges (a bridge's parameter Struct adds the
    rest)."""

    domain_id: Annotated[int, Meta(
        ge=0, description="ROS 2 domain (default ROS_DOMAIN_ID, else 0)")] = msgspec.field(
        default_factory=env_domain_id)
    allow: Annotated[str, Meta(description="regex on ROS names to bridge")] = ".*"
    deny: Annotated[str, Meta(
        description="regex on ROS names never bridged (wins over allow; empty: none)")] = ""


class NameFilter:
    """Whether a name is bridged: it matches ``allow`` and not ``deny`` (deny wins)."""

    def __init__(self, scope: BridgeScope) -> None:
        self.allow = re.compile(scope.allow)
        self.deny = re.compile(scope.deny) if scope.deny else None

    def __call__(self, name: str) -> bool:
        return bool(self.allow.fullmatch(name)) and not (self.deny and self.deny.fullmatch(name))
