"""Node-side parameters: declared with a default that fixes the type; overrides from
``-p name:=value``, a ROS 2 params file, code, or (when present) the shared parameter server."""

from __future__ import annotations

import re
import threading
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Protocol

import yaml

from .errors import (
    InvalidParameterValueError,
    ParameterAlreadyDeclaredError,
    ParameterError,
    ParameterImmutableError,
    ParameterNotDeclaredError,
    ParameterSourceError,
)
from .param_limits import check_value

__all__ = [
    "Parameter",
    "ParameterBackend",
    "Parameters",
    "SetParametersResult",
    "flatten",
    "load_params_file",
    "parse_param_arg",
]

_TYPES = (bool, int, float, str, bytes, list, dict)


@dataclass
class Parameter:
    """One declared parameter."""

    name: str
    value: Any
    type: type
    description: str = ""
    read_only: bool = False
    constraints: dict[str, Any] = field(default_factory=dict)
    """Limits a value must meet (``gt``, ``ge``, ``lt``, ``le``, ``step``, ``choices``,
    ``min_length``, ``max_length``; `zenros.param_limits`); empty for a parameter declared
    without."""
    dynamic_typing: bool = False
    """ROS 2's ``dynamic_typing``: a set may change the type, and setting None
    (``PARAMETER_NOT_SET``) undeclares it; else the declared default fixes the type."""


@dataclass
class SetParametersResult:
    """What a validation callback returns (rclpy's name)."""

    successful: bool
    reason: str = ""


class ParameterBackend(Protocol):
    """A shared store a node's parameters read from and write through (the master)."""

    def fetch(self, name: str) -> tuple[bool, Any]: ...

    def store(self, name: str, value: Any) -> None: ...


def _type_name(t: type) -> str:
    return {bool: "bool", int: "int", float: "float", str: "string", bytes: "bytes",
            list: "list", dict: "dict"}.get(t, t.__name__)


def coerce(name: str, expected: type, value: Any) -> Any:
    """Return ``value`` as ``expected`` or raise `InvalidParameterValueError`."""
    if expected is float and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if expected is bool and not isinstance(value, bool) or expected is int and isinstance(value, bool):
        ok = False
    else:
        ok = isinstance(value, expected)
    if not ok:
        raise InvalidParameterValueError(
            f"parameter {name!r} is {_type_name(expected)}, got {_type_name(type(value))} "
            f"{value!r}"
        )
    return value


def parse_param_arg(arg: str) -> tuple[str, Any]:
    """Parse ``name:=value`` (value read as YAML, as ros2 does)."""
    name, sep, text = arg.partition(":=")
    if not sep or not name:
        raise ParameterSourceError(f"invalid parameter {arg!r}: expected name:=value")
    try:
        value = yaml.safe_load(text) if text != "" else ""
    except yaml.YAMLError as exc:
        raise ParameterSourceError(f"invalid value for parameter {name!r}: {exc}") from exc
    return name, value


def flatten(tree: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """``{a: {b: 1}}`` -> ``{"a.b": 1}`` (ROS 2 nesting)."""
    out: dict[str, Any] = {}
    for k, v in tree.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict) and v:
            out.update(flatten(v, key + "."))
        else:
            out[key] = v
    return out


def load_params_file(path: str | Path, node_fqn: str, *,
                     wildcards: bool = True) -> dict[str, Any]:
    """Parameters for one node from a ROS 2 params file (``node: ros__parameters: ...``).

    Sections match by base name, full name, or (unless ``wildcards`` is False, as rclpy's
    ``use_wildcard``) a wildcard (``/**``, ``/robot1/*``); later, more specific sections win.
    """
    try:
        doc = yaml.safe_load(Path(path).read_text()) or {}
    except (OSError, yaml.YAMLError) as exc:
        raise ParameterSourceError(f"cannot read params file {path}: {exc}") from exc
    if not isinstance(doc, dict):
        raise ParameterSourceError(f"params file {path}: expected a mapping of node names")
    base = node_fqn.rsplit("/", 1)[-1]
    out: dict[str, Any] = {}
    for section, body in _sections(doc):
        pattern = section if section.startswith("/") else None
        matches = section == base or section == node_fqn.lstrip("/") or (
            pattern is not None and (wildcards or "*" not in pattern)
            and _node_pattern(pattern).match(node_fqn) is not None
        )
        if matches:
            if not isinstance(body, dict):
                raise ParameterSourceError(
                    f"params file {path}: ros__parameters of {section} is not a mapping")
            out.update(flatten(body))
    return out


def _node_pattern(pattern: str) -> re.Pattern[str]:
    """ROS 2 node-name wildcards: ``*`` is one name segment (or part of it), ``**`` any number."""
    out = []
    for seg in pattern.strip("/").split("/"):
        if seg == "**":
            out.append("(?:/[^/]+)*")
        else:
            out.append("/" + re.escape(seg).replace(r"\*", "[^/]*"))
    return re.compile("".join(out) + r"\Z")


def _sections(doc: dict[str, Any], prefix: str = "") -> list[tuple[str, Any]]:
    found = []
    for key, val in doc.items():
        if not isinstance(val, dict):
            continue
        if "ros__parameters" in val:
            found.append((prefix + str(key), val["ros__parameters"] or {}))
        else:  # nested namespace: robot1: {chassis: {ros__parameters: ...}}
            found.extend(_sections(val, f"{prefix}{key}/" if prefix or str(key).startswith("/")
                                   else f"/{key}/"))
    return found


Validator = Callable[[list[Parameter]], SetParametersResult]
OnChange = Callable[[Parameter], None]
OnEvent = Callable[[str, Parameter], None]
"""``fn(kind, parameter)``: ``kind`` is "new" (declared), "changed" (set to another value) or
"deleted" (a dynamically typed parameter set to None)."""


class Parameters:
    """The declared parameters of one node."""

    def __init__(self, node_fqn: str, overrides: dict[str, Any] | None = None) -> None:
        self.node = node_fqn
        self.overrides = dict(overrides or {})
        self.backend: ParameterBackend | None = None
        self._params: dict[str, Parameter] = {}
        self._validators: list[Validator] = []
        self._on_change: dict[str | None, list[OnChange]] = {}
        self._on_event: list[OnEvent] = []
        self._lock = threading.RLock()

    def declare(self, name: str, default: Any, *, description: str = "",
                read_only: bool = False, constraints: dict[str, Any] | None = None,
                dynamic_typing: bool = False) -> Any:
        """Declare ``name`` with ``default`` and return its value (the override's, the
        parameter server's, else the default).

        The default fixes the type unless ``dynamic_typing`` (then None, unset, is a default
        too). The value must meet ``constraints`` (`zenros.param_limits`): else
        `InvalidParameterValueError`, and nothing is declared.
        """
        if not name or any(c in name for c in " */$?#"):
            raise ParameterError(f"invalid parameter name {name!r}")
        if not isinstance(default, _TYPES) and not (dynamic_typing and default is None):
            raise InvalidParameterValueError(
                f"parameter {name!r}: default must be bool, int, float, str, bytes, list or "
                f"dict, got {type(default).__name__}"
            )
        with self._lock:
            if name in self._params:
                raise ParameterAlreadyDeclaredError(f"parameter {name!r} is already declared")
            value = default
            for found, given in ((name in self.overrides, self.overrides.get(name)),
                                 self.backend.fetch(name) if self.backend is not None
                                 else (False, None)):
                if found:
                    value = self._typed(name, type(default), given, dynamic_typing)
            why = check_value(value, constraints) if constraints and value is not None else None
            if why is not None:
                raise InvalidParameterValueError(f"parameter {name!r}: {why}")
            p = self._params[name] = Parameter(name, value, type(value), description,
                                               read_only, dict(constraints or {}),
                                               dynamic_typing)
        for fn in list(self._on_event):
            fn("new", p)
        return value

    @staticmethod
    def _typed(name: str, kind: type, value: Any, dynamic: bool) -> Any:
        """``value`` as a parameter of type ``kind`` (any parameter type when ``dynamic``)."""
        if not dynamic:
            return coerce(name, kind, value)
        if value is not None and not isinstance(value, _TYPES):
            raise InvalidParameterValueError(
                f"parameter {name!r} takes bool, int, float, str, bytes, list or dict, got "
                f"{type(value).__name__}")
        return value

    def undeclare(self, name: str) -> None:
        """Forget ``name`` (rclpy's ``undeclare_parameter``: no parameter event); a read-only
        one raises `ParameterImmutableError`, an undeclared one
        `ParameterNotDeclaredError`."""
        with self._lock:
            if self._get(name).read_only:
                raise ParameterImmutableError(f"parameter {name!r} is read-only: it cannot be "
                                              "undeclared")
            del self._params[name]

    def has(self, name: str) -> bool:
        return name in self._params

    def lookup(self, name: str) -> Parameter | None:
        """The declared parameter ``name``, or None."""
        return self._params.get(name)

    def get(self, name: str) -> Any:
        return self._get(name).value

    def _get(self, name: str) -> Parameter:
        try:
            return self._params[name]
        except KeyError:
            known = ", ".join(sorted(self._params)) or "none"
            raise ParameterNotDeclaredError(
                f"parameter {name!r} is not declared on {self.node}; declared: {known}"
            ) from None

    def describe(self) -> list[Parameter]:
        return sorted(self._params.values(), key=lambda p: p.name)

    def set(self, name: str, value: Any, *, write_through: bool = True) -> None:
        """Set a declared parameter; fires on-change callbacks. Checked as ROS 2 does, the
        first refusal wins: read-only, type (any, with ``dynamic_typing``; None then
        undeclares it, a "deleted" event), limits, then the validators."""
        with self._lock:
            p = self._get(name)
            if p.read_only:
                raise ParameterError(f"parameter {name!r} is read-only")
            if value is None and not p.dynamic_typing:
                raise InvalidParameterValueError(
                    f"parameter {name!r} is statically typed ({_type_name(p.type)}): it "
                    "cannot be unset (PARAMETER_NOT_SET) or undeclared by a set")
            typed = self._typed(name, p.type, value, p.dynamic_typing)
            new = replace(p, value=typed, type=type(typed), constraints=dict(p.constraints))
            why = check_value(typed, p.constraints) if p.constraints and typed is not None \
                else None
            for validate in self._validators:
                if why is not None:
                    break
                result = validate([new])
                if not result.successful:
                    why = result.reason or "rejected by node"
            if why is not None:
                raise InvalidParameterValueError(f"parameter {name!r} refused: {why}")
            changed = new.value != p.value or new.type is not p.type
            if typed is None:
                del self._params[name]
            p.value, p.type = new.value, new.type
        if typed is None:
            for ev in list(self._on_event):
                ev("deleted", p)
            return
        if write_through and self.backend is not None:
            self.backend.store(name, p.value)
        if changed:
            self._fire(p)

    def apply_remote(self, name: str, value: Any) -> None:
        """A change pushed by the parameter server: applied if declared and well typed."""
        if name in self._params:
            self.set(name, value, write_through=False)

    def _fire(self, p: Parameter) -> None:
        for fn in self._on_change.get(p.name, []) + self._on_change.get(None, []):
            fn(p)
        for ev in list(self._on_event):
            ev("changed", p)

    def add_validator(self, fn: Validator) -> None:
        """rclpy's add_on_set_parameters_callback: may refuse a change before it happens."""
        self._validators.append(fn)

    def on_event(self, fn: OnEvent) -> None:
        """Call ``fn("new", parameter)`` after each declare and ``fn("changed", parameter)``
        after each change (the node's /parameter_events)."""
        self._on_event.append(fn)

    def on_change(self, fn: OnChange, name: str | None = None) -> None:
        """Call ``fn(parameter)`` after ``name`` (or any parameter) changes."""
        self._on_change.setdefault(name, []).append(fn)
