"""Static transforms from configuration: the ``static_transforms`` parameter's items."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from zenros.errors import InvalidArgumentException, InvalidParameterValueError
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.tf import link_from_numbers, parse_link

__all__ = ["parse_static_transforms"]

_FRAMES = {"parent": ("parent", "frame_id"), "child": ("child", "child_frame_id")}
_EULER = ("yaw", "pitch", "roll")
_QUAT = ("qx", "qy", "qz", "qw")
_KEYS = ("parent", "frame_id", "child", "child_frame_id", "x", "y", "z", *_EULER, *_QUAT)


def parse_static_transforms(
    items: Sequence[Any], stamp: Time | None = None, name: str = "static_transforms"
) -> list[TransformStamped]:
    """The links given in a parameter: a list whose items are each either

    - a string, as static_transform_publisher's arguments:
      ``"x y z yaw pitch roll parent child"`` or ``"x y z qx qy qz qw parent child"``;
    - a mapping ``{parent, child, x, y, z, yaw, pitch, roll}`` or with ``qx qy qz qw``
      instead of the angles (``frame_id``/``child_frame_id`` may replace
      ``parent``/``child``; missing numbers are 0, a missing quaternion is identity).

    Raises:
        InvalidParameterValueError: an item of neither form; the message names the item
            (``static_transforms[2]``) and what is wrong.
    """
    if isinstance(items, (str, bytes)) or not isinstance(items, Sequence):
        raise InvalidParameterValueError(
            f"parameter {name!r}: expected a list of transforms, got {type(items).__name__}"
        )
    out = []
    for i, item in enumerate(items):
        where = f"parameter {name!r}[{i}]"
        try:
            if isinstance(item, str):
                out.append(parse_link(item, stamp))
            elif isinstance(item, dict):
                out.append(_from_mapping(item, stamp, where))
            else:
                raise InvalidParameterValueError(
                    f"{where}: expected a string 'x y z yaw pitch roll parent child' or a "
                    f"mapping, got {type(item).__name__} {item!r}"
                )
        except InvalidArgumentException as exc:
            raise InvalidParameterValueError(f"{where}: {exc}") from exc
    children = [t.child_frame_id for t in out]
    dup = sorted({c for c in children if children.count(c) > 1})
    if dup:
        raise InvalidParameterValueError(
            f"parameter {name!r}: child frame(s) {', '.join(dup)} given more than once; "
            "a frame has one parent"
        )
    return out


def _from_mapping(d: dict[str, Any], stamp: Time | None, where: str) -> TransformStamped:
    unknown = sorted(str(k) for k in d if k not in _KEYS)
    if unknown:
        raise InvalidParameterValueError(
            f"{where}: unknown key(s) {', '.join(unknown)}; valid: {', '.join(_KEYS)}"
        )
    frames = {}
    for role, keys in _FRAMES.items():
        given = [d[k] for k in keys if k in d]
        if len(given) != 1 or not isinstance(given[0], str) or not given[0]:
            raise InvalidParameterValueError(
                f"{where}: expected one non-empty string for {' or '.join(keys)}"
            )
        frames[role] = given[0]
    euler = any(k in d for k in _EULER)
    quat = any(k in d for k in _QUAT)
    if euler and quat:
        raise InvalidParameterValueError(
            f"{where}: give the rotation as yaw/pitch/roll or as qx/qy/qz/qw, not both"
        )
    keys = ("x", "y", "z", *(_QUAT if quat else _EULER))
    defaults = {"qw": 1.0}
    numbers = []
    for k in keys:
        v = d.get(k, defaults.get(k, 0.0))
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InvalidParameterValueError(
                f"{where}: {k} must be a number, got {type(v).__name__} {v!r}"
            )
        numbers.append(float(v))
    return link_from_numbers(numbers, frames["parent"], frames["child"], stamp)
