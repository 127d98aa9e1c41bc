"""`CoverageLink`: nav's ``compute_coverage_path`` service (docs/robot-api.md §6.12), refusals as
port errors."""

from __future__ import annotations

from zenros.msgs.zenros_msgs import (
    ComputeCoveragePath,
    ComputeCoveragePathRequest,
    ComputeCoveragePathResponse,
)
from zenros.node import Node

from ..errors import Refused
from ..state.presence import Presence
from .calls import call_port

__all__ = ["CoverageLink"]


class CoverageLink:
    """``await plan(request)``: a coverage path, planned by nav (computed only, never driven)."""

    def __init__(self, node: Node, presence: Presence, timeout: float = 30.0) -> None:
        self.presence = presence
        self.timeout = timeout
        self.client = node.create_client(ComputeCoveragePath, "compute_coverage_path")

    async def plan(self, req: ComputeCoveragePathRequest) -> ComputeCoveragePathResponse:
        client = self.client
        res: ComputeCoveragePathResponse = await call_port(
            client, req, self.timeout, lambda: self.presence.error("nav", f"no server for {client.name}"),
            "the nav service", lambda exc: Refused(exc.reason))
        return res
