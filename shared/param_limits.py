"""The limits a parameter's value must meet, checked and worded one way everywhere.

Limits are a plain mapping (what `zenros.param_describe` sends and `zenros param describe`
shows): ``gt``, ``ge``, ``lt``, ``le`` for numbers, with ``step`` (ROS 2's range step: from
the lower bound, the upper bound always allowed; 0 or absent, any value); ``choices``;
``min_length``, ``max_length`` for strings and lists. A configuration Struct's
``msgspec.Meta`` gives them (`zenros.param_config`), as does a ROS 2 ``ParameterDescriptor``'s
range (`zenros.node.Node.declare_parameter`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

__all__ = ["check_value", "describe_constraints"]

_OPS = {"gt": ">", "ge": ">=", "lt": "<", "le": "<="}
STEP_TOLERANCE = 1e-6
"""rclpy's: a double is on its step when within this share of the step of one."""


def describe_constraints(constraints: Mapping[str, Any]) -> str:
    """``{"ge": 0, "le": 1}`` -> ``"within 0 .. 1"``; ``{"gt": 0}`` -> ``"> 0"``;
    ``{"ge": 2, "le": 5, "step": 2}`` -> ``"within 2 .. 5 in steps of 2 from 2"``."""
    if "choices" in constraints:
        return "one of " + ", ".join(str(c) for c in constraints["choices"])
    bounds = {k: v for k, v in constraints.items() if k in _OPS}
    if set(bounds) == {"ge", "le"}:
        parts = [f"within {bounds['ge']:g} .. {bounds['le']:g}"]
    else:
        parts = [f"{_OPS[k]} {v:g}" for k, v in bounds.items()]
    step = constraints.get("step") or 0
    lo = constraints.get("ge", constraints.get("gt"))
    if step and lo is not None and parts:
        parts[-1] += f" in steps of {step:g} from {lo:g}"
    if "min_length" in constraints:
        parts.append(f"at least {constraints['min_length']} long")
    if "max_length" in constraints:
        parts.append(f"at most {constraints['max_length']} long")
    return " and ".join(parts)


def _off_step(value: float, constraints: Mapping[str, Any]) -> bool:
    """Whether a number in range misses the range's step (ROS 2's rule: counted from the
    lower bound; the bounds themselves always pass)."""
    step = constraints.get("step") or 0
    lo = constraints.get("ge", constraints.get("gt"))
    hi = constraints.get("le", constraints.get("lt"))
    if not step or lo is None or value == lo or value == hi:
        return False
    if isinstance(value, int) and isinstance(step, int) and isinstance(lo, int):
        return bool((value - lo) % step != 0)
    n = round((value - lo) / step)
    return bool(abs(lo + n * step - value) > STEP_TOLERANCE * abs(step))


def check_value(value: Any, constraints: Mapping[str, Any]) -> str | None:
    """Why ``value`` breaks ``constraints`` ("expected ..., got ..."), or None."""
    if isinstance(value, float) and not math.isfinite(value):
        return f"expected a finite number, got {value!r}"
    bad = False
    if "choices" in constraints:
        bad = value not in constraints["choices"]
    elif isinstance(value, int | float) and not isinstance(value, bool):
        bad = (("gt" in constraints and not value > constraints["gt"])
               or ("ge" in constraints and not value >= constraints["ge"])
               or ("lt" in constraints and not value < constraints["lt"])
               or ("le" in constraints and not value <= constraints["le"])
               or _off_step(value, constraints))
        if bad:
            what = "an int" if isinstance(value, int) else "a finite number"
            return f"expected {what} {describe_constraints(constraints)}, got {value!r}"
    elif hasattr(value, "__len__"):
        bad = (len(value) < constraints.get("min_length", 0)
               or len(value) > constraints.get("max_length", math.inf))
    if bad:
        return f"expected {describe_constraints(constraints)}, got {value!r}"
    return None
