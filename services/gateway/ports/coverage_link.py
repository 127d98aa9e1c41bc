"""`CoverageLink`: nav's ``compute_coverage_path`` service (docs/robot-api.md §6.12), refusals as
port errors."""

from __future__ import annotations

from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.msgs.zenros_msgs import (
    ComputeCoveragePath,
    ComputeCoveragePathRequest,
    ComputeCoveragePathResponse,
)
from zenros.node import Node

from ..errors import NoAnswer, Refused
from ..state.presence import Presence

__all__ = ["CoverageLink"]


class CoverageLink:
    """``await plan(request)``: a coverage path, planned by nav (computed only, never driven)."""

    def __init__(self, node: Node, presence: Presence, timeout: float = 30.0) -> None:
        self.presence = presence
        self.timeout = timeout
        self.client = node.create_client(ComputeCoveragePath, "compute_coverage_path")

    async def plan(self, req: ComputeCoveragePathRequest) -> ComputeCoveragePathResponse:
        client, timeout = self.client, self.timeout
        try:
            res: ComputeCoveragePathResponse = await client.call_async(req, timeout)
        except ServiceUnavailableError:
            raise self.presence.error("nav", f"no server for {client.name}") from None
        except ZenrosTimeout:
            raise NoAnswer(f"the nav service did not answer {client.name} within "
                           f"{timeout:g} s") from None
        except ServiceError as exc:
            raise Refused(exc.reason) from exc
        return res
