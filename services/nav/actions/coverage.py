"""`handle_compute_coverage_path`: the ``compute_coverage_path`` service over `plan_coverage`."""

from __future__ import annotations

from zenros.msgs.geometry_msgs import Point
from zenros.msgs.zenros_msgs.nav import ComputeCoveragePathRequest, ComputeCoveragePathResponse

from ..planning.coverage import plan_coverage, validate_field

__all__ = ["handle_compute_coverage_path"]


def handle_compute_coverage_path(req: ComputeCoveragePathRequest
                                 ) -> ComputeCoveragePathResponse:
    """Plan (never drive) the coverage path; a bad request raises `CoverageError`, which
    reaches the caller as a `ServiceError` naming the problem."""
    field = validate_field([(p.x, p.y) for p in req.border],
                           [[(p.x, p.y) for p in h.points] for h in req.holes])
    plan = plan_coverage(field, req.op_width, req.swath_angle, req.headland_width,
                         req.turn_radius)
    return ComputeCoveragePathResponse(
        path=[Point(x=float(x), y=float(y)) for x, y in plan.path.tolist()],
        swath_angle=plan.swath_angle, swaths=plan.swaths, segments=plan.segments)
