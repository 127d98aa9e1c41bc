"""A static link written as text, as static_transform_publisher takes it:
``x y z yaw pitch roll parent child`` or ``x y z qx qy qz qw parent child``."""

from __future__ import annotations

import math
from collections.abc import Sequence

from ..errors import InvalidArgumentException
from ..msgs.builtin_interfaces import Time
from ..msgs.geometry_msgs import TransformStamped
from .convert import transform_stamped
from .quaternion import quaternion_from_euler

__all__ = ["FORMS", "link_from_numbers", "parse_link"]

FORMS = "'x y z yaw pitch roll parent child' or 'x y z qx qy qz qw parent child'"


def link_from_numbers(
    numbers: Sequence[float], parent: str, child: str, stamp: Time | None = None
) -> TransformStamped:
    """The link ``parent → child`` from 6 numbers (x y z yaw pitch roll, radians) or 7
    (x y z qx qy qz qw; the quaternion is normalised).

    Raises:
        InvalidArgumentException: another count, a non-finite number, a zero quaternion,
            an empty frame id, or parent == child.
    """
    vals = [float(v) for v in numbers]
    where = f"static transform {parent or '?'} -> {child or '?'}"
    if len(vals) not in (6, 7):
        raise InvalidArgumentException(
            f"{where}: expected 6 numbers (x y z yaw pitch roll) or 7 (x y z qx qy qz qw), "
            f"got {len(vals)}"
        )
    if not all(math.isfinite(v) for v in vals):
        raise InvalidArgumentException(f"{where}: numbers must be finite, got {vals}")
    if not parent.removeprefix("/") or not child.removeprefix("/"):
        raise InvalidArgumentException(f"{where}: parent and child frame ids must not be empty")
    if parent.removeprefix("/") == child.removeprefix("/"):
        raise InvalidArgumentException(f"{where}: a frame cannot be its own parent")
    if len(vals) == 6:
        yaw, pitch, roll = vals[3:]
        q = quaternion_from_euler(roll, pitch, yaw)
    else:
        n = math.sqrt(sum(c * c for c in vals[3:]))
        if n < 1e-9:
            raise InvalidArgumentException(f"{where}: the quaternion {vals[3:]} has no length")
        q = (vals[3] / n, vals[4] / n, vals[5] / n, vals[6] / n)
    return transform_stamped(parent, child, (vals[0], vals[1], vals[2], *q), stamp)


def parse_link(text: str | Sequence[str], stamp: Time | None = None) -> TransformStamped:
    """A link from static_transform_publisher's arguments, as one string or as tokens.

    Raises:
        InvalidArgumentException: not one of the two forms (the message shows both).
    """
    tokens = text.split() if isinstance(text, str) else [str(t) for t in text]
    if len(tokens) not in (8, 9):
        raise InvalidArgumentException(
            f"expected {FORMS}; got {len(tokens)} values: {' '.join(tokens)!r}"
        )
    *nums, parent, child = tokens
    try:
        numbers = [float(n) for n in nums]
    except ValueError:
        bad = next(n for n in nums if not _is_float(n))
        raise InvalidArgumentException(
            f"expected a number, got {bad!r} in {' '.join(tokens)!r}; the forms are {FORMS}"
        ) from None
    return link_from_numbers(numbers, parent, child, stamp)


def _is_float(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True
