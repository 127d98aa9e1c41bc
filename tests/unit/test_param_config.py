"""param_config: a msgspec Struct declared as parameters: defaults, limits, descriptions,
refused values naming the parameter, live changes checked and followed."""

from __future__ import annotations

from typing import Annotated, Literal

import msgspec
import pytest
from msgspec import Meta
from zenros.errors import InvalidParameterValueError
from zenros.param_config import declare_parameters, describe_constraints, parameter_specs
from zenros.param_describe import describe
from zenros.params import Parameters


class TalkerConfig(msgspec.Struct, kw_only=True):
    rate: Annotated[float, Meta(gt=0, description="messages per second")] = 2.0
    share: Annotated[float, Meta(ge=0, le=1)] = 0.5
    retries: Annotated[int, Meta(ge=0)] = 3
    mode: Literal["fast", "slow"] = "fast"
    pose: Annotated[list[float], Meta(max_length=3)] = msgspec.field(default_factory=list)
    frame: str = "map"
    loud: bool = False


class Frozen(msgspec.Struct, frozen=True):
    rate: Annotated[float, Meta(gt=0)] = 1.0


def test_defaults_and_overrides_become_the_config() -> None:
    params = Parameters("/talker", {"rate": 5, "mode": "slow", "pose": [1, 2]})
    cfg = declare_parameters(params, TalkerConfig)
    assert cfg == TalkerConfig(rate=5.0, mode="slow", pose=[1.0, 2.0])
    assert isinstance(cfg.rate, float)
    assert [p.name for p in params.describe()] == sorted(
        ["rate", "share", "retries", "mode", "pose", "frame", "loud"])


def test_descriptions_and_limits_are_described() -> None:
    params = Parameters("/talker")
    declare_parameters(params, TalkerConfig, read_only=True)
    found = describe(params)
    assert found["rate"] == {"type": "float", "description": "messages per second",
                             "read_only": True, "constraints": {"gt": 0}}
    assert found["mode"]["constraints"] == {"choices": ["fast", "slow"]}
    assert found["pose"]["constraints"] == {"max_length": 3}
    assert "constraints" not in found["frame"]
    assert describe_constraints({"ge": 0, "le": 1}) == "within 0 .. 1"
    assert describe_constraints({"gt": 0}) == "> 0"


@pytest.mark.parametrize(("values", "match"), [
    ({"rate": 0.0}, "parameter 'rate': expected a finite number > 0, got 0.0"),
    ({"rate": float("inf")}, "parameter 'rate': expected a finite number, got inf"),
    ({"share": 1.5}, "parameter 'share': expected a finite number within 0 .. 1, got 1.5"),
    ({"retries": -1}, "parameter 'retries': expected an int >= 0, got -1"),
    ({"mode": "warp"}, "parameter 'mode': expected one of fast, slow, got 'warp'"),
    ({"pose": [1.0, 2.0, 3.0, 4.0]}, "parameter 'pose': expected at most 3 long"),
    ({"pose": [1.0, "a"]}, "parameter 'pose': Expected `float`, got `str`"),
    ({"rate": "fast"}, "parameter 'rate' is float, got string 'fast'"),
])
def test_bad_values_name_the_parameter_and_the_limit(values: dict[str, object],
                                                     match: str) -> None:
    with pytest.raises(InvalidParameterValueError, match=match):
        declare_parameters(Parameters("/talker", values), TalkerConfig)


def test_live_changes_are_checked_and_followed() -> None:
    params = Parameters("/talker")
    cfg = declare_parameters(params, TalkerConfig)
    params.set("rate", 10.0)
    params.set("mode", "slow")
    assert cfg.rate == 10.0 and cfg.mode == "slow"
    with pytest.raises(InvalidParameterValueError, match="'share' refused: expected a finite "
                                                         "number within 0 .. 1, got 2.0"):
        params.set("share", 2.0)
    assert cfg.share == 0.5 and params.get("share") == 0.5


def test_a_frozen_config_is_a_snapshot() -> None:
    params = Parameters("/n")
    cfg = declare_parameters(params, Frozen)
    params.set("rate", 3.0)
    assert cfg.rate == 1.0 and params.get("rate") == 3.0
    with pytest.raises(InvalidParameterValueError, match="'rate' refused"):
        params.set("rate", -1.0)


def test_a_field_without_a_default_or_of_another_type_is_a_programming_error() -> None:
    class NoDefault(msgspec.Struct):
        rate: float

    class Odd(msgspec.Struct):
        when: complex = 1j

    with pytest.raises(TypeError, match="NoDefault.rate: a parameter needs a default"):
        parameter_specs(NoDefault)
    with pytest.raises(TypeError, match="Odd.when"):
        parameter_specs(Odd)


def test_a_prefix_names_each_parameter_and_is_followed() -> None:
    params = Parameters("/planner", {"GridBased.rate": 4, "rate": 9})
    cfg = declare_parameters(params, TalkerConfig, prefix="GridBased.")
    assert cfg.rate == 4.0 and params.get("GridBased.mode") == "fast"
    assert not params.has("rate")  # only the prefixed names are declared
    with pytest.raises(InvalidParameterValueError, match="> 0"):
        params.set("GridBased.rate", -1.0)
    params.set("GridBased.share", 0.25)
    assert cfg.share == 0.25
    with pytest.raises(InvalidParameterValueError, match="parameter 'Other.share'"):
        declare_parameters(Parameters("/p", {"Other.share": 2.0}), TalkerConfig,
                           prefix="Other.")
