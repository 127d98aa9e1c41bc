"""declare_parameters(Config): a node's parameters declared from one msgspec Struct.

The Struct is a service's configuration: each field is one parameter, its default the only
default, its ``Annotated[..., msgspec.Meta(ge=..., le=..., description=...)]`` the limits and
the description that ``zenros param describe`` shows. A ``Literal`` field takes one of its
values. Numbers must be finite. Declaring returns an instance holding the current values; when
the Struct is not frozen, the instance follows later parameter changes, and changes that break
a limit are refused before they happen::

    class TalkerConfig(msgspec.Struct, kw_only=True):
        rate: Annotated[float, msgspec.Meta(gt=0, description="messages per second")] = 2.0

    cfg = node.declare_parameters(TalkerConfig)   # cfg.rate is 2.0, or the override
"""

from __future__ import annotations

import typing
from dataclasses import dataclass
from typing import Any, TypeVar

import msgspec
import msgspec.inspect as mi

from .errors import InvalidParameterValueError
from .param_limits import check_value, describe_constraints
from .params import Parameter, Parameters, SetParametersResult

__all__ = ["ParameterSpec", "check_value", "declare_parameters", "describe_constraints",
           "parameter_specs"]

C = TypeVar("C", bound=msgspec.Struct)

_BOUNDS = ("gt", "ge", "lt", "le")


@dataclass(frozen=True)
class ParameterSpec:
    """One field of a configuration Struct, as a parameter."""

    name: str
    default: Any
    description: str
    constraints: dict[str, Any]


def parameter_specs(config: type[msgspec.Struct]) -> list[ParameterSpec]:
    """The parameters a configuration Struct declares, in field order.

    Raises:
        TypeError: a field without a default, or of a type a parameter cannot hold.
    """
    hints = typing.get_type_hints(config, include_extras=True)
    info = mi.type_info(config)
    if not isinstance(info, mi.StructType):
        raise TypeError(f"{config.__name__} is not a msgspec Struct")
    specs = []
    for f, field in zip(info.fields, msgspec.structs.fields(config), strict=True):
        if field.default is not msgspec.NODEFAULT:
            default = field.default
        elif field.default_factory is not msgspec.NODEFAULT:
            default = field.default_factory()
        else:
            raise TypeError(f"{config.__name__}.{f.name}: a parameter needs a default")
        kind, description = f.type, ""
        if isinstance(kind, mi.Metadata):
            description = str((kind.extra_json_schema or {}).get("description", ""))
            kind = kind.type
        constraints: dict[str, Any] = {}
        if isinstance(kind, mi.FloatType | mi.IntType):
            constraints = {b: getattr(kind, b) for b in _BOUNDS if getattr(kind, b) is not None}
            if isinstance(kind, mi.FloatType):
                default = float(default)
        elif isinstance(kind, mi.LiteralType):
            constraints = {"choices": list(kind.values)}
        elif isinstance(kind, mi.ListType | mi.StrType):
            constraints = {b: getattr(kind, b) for b in ("min_length", "max_length")
                           if getattr(kind, b) is not None}
        elif not isinstance(kind, mi.BoolType | mi.BytesType | mi.DictType):
            raise TypeError(f"{config.__name__}.{f.name}: {hints[f.name]!r} cannot be a "
                            "parameter (bool, int, float, str, bytes, list, dict or Literal)")
        specs.append(ParameterSpec(f.name, default, description, constraints))
    return specs


def _refusal(value: Any, spec: ParameterSpec, hint: Any) -> str | None:
    why = check_value(value, spec.constraints)
    if why is None:  # what the constraints do not say: the items of a list, say
        try:
            msgspec.convert(value, hint)
        except msgspec.ValidationError as exc:
            why = str(exc)
    return why


def declare_parameters(params: Parameters, config: type[C], *, read_only: bool = False,
                       prefix: str = "") -> C:
    """Declare every field of ``config`` on ``params`` and return the values as a ``config``.

    Args:
        params: the node's parameters (``node.parameters``).
        config: a msgspec Struct whose fields all have defaults.
        read_only: declare every parameter read-only.
        prefix: put before each field's name (``"GridBased."``: Nav2's per-plugin names,
            ``GridBased.tolerance``, as a params file's nested mapping flattens to).

    Returns:
        The configuration with each parameter's current value (override, params file or
        parameter server, else the field's default). Unless ``config`` is frozen, it is
        updated in place after each accepted change of one of its parameters.

    Raises:
        InvalidParameterValueError: a value of the wrong type or out of its limits (the
            message names the parameter and the limits).
    """
    specs = {prefix + s.name: s for s in parameter_specs(config)}
    hints = typing.get_type_hints(config, include_extras=True)
    values = {}
    for name, s in specs.items():
        value = params.declare(name, s.default, description=s.description,
                               read_only=read_only, constraints=s.constraints)
        why = _refusal(value, s, hints[s.name])
        if why is not None:
            raise InvalidParameterValueError(f"parameter {name!r}: {why}")
        values[s.name] = value
    try:
        cfg = msgspec.convert(values, config)
    except msgspec.ValidationError as exc:  # a limit check_value does not know
        raise InvalidParameterValueError(f"{config.__name__}: {exc}") from None

    def validate(changed: list[Parameter]) -> SetParametersResult:
        for p in changed:
            if p.name in specs:
                spec = specs[p.name]
                why = _refusal(p.value, spec, hints[spec.name])
                if why is not None:
                    return SetParametersResult(False, why)
        return SetParametersResult(True)

    params.add_validator(validate)
    if not config.__struct_config__.frozen:
        for name, spec in specs.items():
            params.on_change(lambda p, field=spec.name: setattr(cfg, field, p.value), name)
    return cfg
