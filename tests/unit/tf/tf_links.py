"""What the TF unit tests build links with: times in seconds and one `link` maker."""

from __future__ import annotations

from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.tf import quaternion_from_yaw, transform_stamped

__all__ = ["NS", "T", "link"]

NS = 1_000_000_000


def T(sec: float) -> Time:
    """A stamp ``sec`` seconds after the epoch."""
    return Time.from_nanoseconds(round(sec * NS))


def link(
    parent: str, child: str, t: float = 0.0, x: float = 0.0, y: float = 0.0, z: float = 0.0,
    yaw: float = 0.0, q: tuple[float, float, float, float] | None = None,
) -> TransformStamped:
    """``parent -> child`` at time ``t``: a translation and a yaw (or a quaternion ``q``)."""
    rot = q if q is not None else quaternion_from_yaw(yaw)
    return transform_stamped(parent, child, (x, y, z, *rot), T(t))
