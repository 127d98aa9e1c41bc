"""ROS 2's ``ParameterDescriptor`` and zenros's declared parameters, each way.

A zenros parameter keeps its limits as a mapping (`zenros.param_limits`); ROS 2 describes
them as a ``FloatingPointRange`` or ``IntegerRange`` (inclusive bounds and a step) with what a
range cannot say in the free text ``additional_constraints``. `describe_parameter` gives the
descriptor a ``~/describe_parameters`` call answers; `descriptor_spec` reads one a node
declares a parameter with (``Node.declare_parameter(name, value, descriptor)``, as rclpy).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any

from .msgs.rcl_interfaces import FloatingPointRange, IntegerRange, ParameterDescriptor
from .param_events import to_parameter_value
from .params import Parameter

__all__ = ["ADDITIONAL", "DescriptorSpec", "describe_parameter", "descriptor_spec"]

_RANGE_KEYS = ("gt", "ge", "lt", "le", "step")
ADDITIONAL = "additional_constraints"
"""The limits key that keeps a descriptor's free-text ``additional_constraints``."""
_INT64 = (-(2**63), 2**63 - 1)


@dataclass(frozen=True)
class DescriptorSpec:
    """What a ``ParameterDescriptor`` asks of a parameter being declared."""

    description: str = ""
    read_only: bool = False
    dynamic_typing: bool = False
    constraints: dict[str, Any] = field(default_factory=dict)


def descriptor_spec(d: ParameterDescriptor) -> DescriptorSpec:
    """A descriptor's flags and limits: its range as ``ge``/``le`` (an infinite or int64
    bound is no bound) and ``step`` (0: any value), its ``additional_constraints`` text kept
    as it is (described, not checked)."""
    c: dict[str, Any] = {}
    rng: FloatingPointRange | IntegerRange | None = None
    if d.floating_point_range:
        rng = d.floating_point_range[0]
    elif d.integer_range:
        rng = d.integer_range[0]
    if rng is not None:
        lo, hi = min(rng.from_value, rng.to_value), max(rng.from_value, rng.to_value)
        if math.isfinite(lo) and lo != _INT64[0]:
            c["ge"] = lo
        if math.isfinite(hi) and hi != _INT64[1]:
            c["le"] = hi
        if rng.step:
            c["step"] = rng.step
    if d.additional_constraints:
        c[ADDITIONAL] = d.additional_constraints
    return DescriptorSpec(d.description, d.read_only, d.dynamic_typing, c)


def describe_parameter(p: Parameter) -> ParameterDescriptor:
    """``p`` as ROS 2 describes a parameter: its type, description, read-only and dynamic
    typing flags, and its limits as a range (a number's ``ge``/``gt`` and ``le``/``lt``, its
    ``step``; an open bound is the largest value of its type) with what a range cannot say
    in ``additional_constraints`` (JSON, or the text the parameter was declared with)."""
    d = ParameterDescriptor(name=p.name, type=to_parameter_value(p.value).type,
                            description=p.description, read_only=p.read_only,
                            dynamic_typing=p.dynamic_typing)
    c = p.constraints
    numeric = p.type in (int, float)
    if numeric and any(k in c for k in _RANGE_KEYS):
        lo = c.get("ge", c.get("gt"))
        hi = c.get("le", c.get("lt"))
        step = c.get("step") or 0
        if p.type is float:
            d.floating_point_range = [FloatingPointRange(
                from_value=-math.inf if lo is None else float(lo),
                to_value=math.inf if hi is None else float(hi), step=float(step))]
        else:
            d.integer_range = [IntegerRange(
                from_value=_INT64[0] if lo is None else int(lo),
                to_value=_INT64[1] if hi is None else int(hi), step=int(step))]
    rest = {k: v for k, v in c.items() if not (numeric and k in _RANGE_KEYS) and k != ADDITIONAL}
    if "gt" in c or "lt" in c:
        rest.update({k: c[k] for k in ("gt", "lt") if k in c})  # open bounds, stated
    if rest:
        d.additional_constraints = json.dumps(rest, sort_keys=True, default=repr)
    elif ADDITIONAL in c:
        d.additional_constraints = str(c[ADDITIONAL])
    return d
