"""REST ``POST /navigation/coverage_path`` (docs/robot-api.md §6.12): a boustrophedon coverage path,
planned by the nav service's ``compute_coverage_path`` (computed only, never driven)."""

from __future__ import annotations

import math
from typing import Annotated

import msgspec
from zenros.msgs.geometry_msgs import Point
from zenros.msgs.zenros_msgs import ComputeCoveragePathRequest, CoverageHole

from ..api import Answer, Api, ApiError, Call
from ..fields import Coord

__all__ = ["CoverageBody", "add_coverage_routes"]

MAX_POINTS = 10_000
Xyz = Annotated[list[Coord], msgspec.Meta(min_length=2, max_length=3)]
Polygon = Annotated[list[Xyz], msgspec.Meta(min_length=3, max_length=MAX_POINTS)]
Metres = Annotated[float, msgspec.Meta(ge=0.0, le=1000.0)]


class CoverageBody(msgspec.Struct, forbid_unknown_fields=True):
    """The §6.12 request: ``op_width`` and ``border`` are required."""

    op_width: Annotated[float, msgspec.Meta(gt=0.0, le=1000.0)]
    border: Polygon
    swath_angle: Annotated[float, msgspec.Meta(ge=-360.0, le=360.0)] = 0.0
    turn_radius: Metres = 0.0
    headland_width: Metres = 0.0
    holes: Annotated[list[Polygon], msgspec.Meta(max_length=1000)] = msgspec.field(
        default_factory=list)


def _points(poly: list[list[float]]) -> list[Point]:
    return [Point(x=p[0], y=p[1], z=p[2] if len(p) > 2 else 0.0) for p in poly]


async def post_coverage_path(call: Call[CoverageBody, None]) -> Answer:
    """Plan (not drive) a back-and-forth path covering ``border`` minus ``holes``."""
    b = call.body
    for name in ("op_width", "swath_angle", "turn_radius", "headland_width"):
        if not math.isfinite(getattr(b, name)):
            raise ApiError(400, f"{name} must be a finite number")
    total = len(b.border) + sum(len(h) for h in b.holes)
    if total > MAX_POINTS:
        raise ApiError(400, f"border and holes have {total} points (limit {MAX_POINTS})")
    req = ComputeCoveragePathRequest(
        swath_angle=b.swath_angle, op_width=b.op_width, turn_radius=b.turn_radius,
        headland_width=b.headland_width, border=_points(b.border),
        holes=[CoverageHole(points=_points(h)) for h in b.holes])
    res = await call.ctx.coverage.plan(req)
    return {"status": "ok", "path": [[p.x, p.y, 0.0] for p in res.path],
            "swath_angle": res.swath_angle, "swaths": res.swaths}


def add_coverage_routes(api: Api) -> None:
    """Route the coverage-path operation to nav's service (``call.ctx.coverage``)."""
    api.add("POST", "/navigation/coverage_path", post_coverage_path)
