"""Parameter types the chassis's Structs share: limits as `Annotated` types, a pose list."""

from __future__ import annotations

import math
from typing import Annotated

from msgspec import Meta
from zenros.se2 import Pose2

__all__ = ["NonNegative", "PoseList", "Positive", "pose_from"]

Positive = Annotated[float, Meta(gt=0)]
NonNegative = Annotated[float, Meta(ge=0)]
PoseList = Annotated[list[float], Meta(max_length=3,
                                       description="[x, y, theta] in map; [] = the map's")]


def pose_from(name: str, value: list[float]) -> Pose2 | None:
    """The pose a `PoseList` parameter names, None for ``[]``.

    Raises:
        ValueError: not ``[x, y]`` or ``[x, y, theta]`` of finite numbers (names ``name``).
    """
    if not value:
        return None
    if len(value) not in (2, 3) or not all(math.isfinite(v) for v in value):
        raise ValueError(
            f"parameter {name!r}: expected [x, y] or [x, y, theta] (finite numbers), "
            f"got {value!r}")
    x, y, *theta = value
    return Pose2(x, y, theta[0] if theta else 0.0)
