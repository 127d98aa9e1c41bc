"""Parameter names and values: resolution against a caller, validation, flattening of dicts."""

from __future__ import annotations

import copy
import re
from collections.abc import Iterator, Mapping
from typing import Any

import msgspec
from zenros.errors import InvalidNameError, InvalidParameterValueError
from zenros.names import MAX_NAME_LENGTH, join, namespace_of, resolve, validate_name

__all__ = [
    "MAX_NAME_LENGTH",
    "MAX_VALUE_BYTES",
    "VALUE_TYPES",
    "Value",
    "ancestors",
    "canonical",
    "check_size",
    "check_value",
    "copy_value",
    "flatten",
    "is_under",
    "resolve_param_name",
]

Value = Any
"""A parameter value: bool, int, float, str, bytes, or a list or str-keyed dict of those."""

VALUE_TYPES = "bool, int, float, str, bytes, list, dict"
MAX_VALUE_BYTES = 1 << 20
"""The largest value one write may set (a dict set at once counts whole), MessagePack-encoded.

Parameters are configuration, read by every node at startup and sent to every replica and
subscriber on change; bulk data belongs on a topic."""
_INT_MIN = -(2**63)
_INT_MAX = 2**64 - 1
_SEGMENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def resolve_param_name(name: str, node: str | None = None, namespace: str | None = None) -> str:
    """Resolve a parameter name as the caller sees it, to its absolute form.

    Args:
        name: ``/global``, ``relative`` (to ``namespace``), or private ``~x`` / ``~/x``
            (under the node's own name, as in ROS 1).
        node: the caller's fully qualified node name, e.g. ``/robot1/nav``.
        namespace: the caller's namespace; defaults to the namespace of ``node``, else ``/``.

    Returns:
        The absolute name, e.g. ``/robot1/nav/max_speed``.

    Raises:
        InvalidNameError: the name breaks the ROS rules, or is private with no node given.
    """
    if name.startswith("~") and len(name) > 1 and name[1] != "/":
        name = "~/" + name[1:]
    if namespace is None:
        namespace = namespace_of(node) if node else "/"
    resolved: str = resolve(name, namespace, node, kind="parameter")
    return resolved


def canonical(name: str) -> str:
    """Check an absolute parameter name (``/`` is the root) and return it."""
    if not name.startswith("/"):
        raise InvalidNameError(
            f"invalid parameter name {name!r}: the store takes absolute names (starting with '/');"
            " resolve relative and private names with resolve_param_name() first"
        )
    validate_name(name, "parameter")
    return name


def ancestors(name: str) -> Iterator[str]:
    """Strict ancestors of an absolute name, nearest first: ``/a/b/c`` → ``/a/b``, ``/a``, ``/``."""
    while name != "/":
        name = namespace_of(name)
        yield name


def is_under(name: str, prefix: str) -> bool:
    """True if ``name`` is ``prefix`` itself or lies in the namespace ``prefix``."""
    return prefix == "/" or name == prefix or name.startswith(prefix + "/")


def check_value(value: Any, where: str) -> Value:
    """Validate a parameter value and return a normalized copy (tuples become lists).

    Raises:
        InvalidParameterValueError: a type outside bool, int, float, str, bytes, list, dict,
            an int outside 64 bits, or a dict key that is not a string.
    """
    if isinstance(value, (bool, float, str)):
        return value
    if isinstance(value, int):
        if not _INT_MIN <= value <= _INT_MAX:
            raise InvalidParameterValueError(
                f"parameter {where}: int {value} does not fit in 64 bits"
            )
        return value
    if isinstance(value, (bytes, bytearray, memoryview)):
        return bytes(value)
    if isinstance(value, (list, tuple)):
        return [check_value(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, Mapping):
        out: dict[str, Value] = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise InvalidParameterValueError(
                    f"parameter {where}: dict keys must be str, got {type(k).__name__} {k!r}"
                )
            out[k] = check_value(v, f"{where}.{k}")
        return out
    got = "null" if value is None else type(value).__name__
    raise InvalidParameterValueError(
        f"parameter {where}: unsupported value {got}; valid types are {VALUE_TYPES}"
    )


def check_size(value: Value, where: str) -> None:
    """Refuse a value larger than `MAX_VALUE_BYTES` once encoded.

    Raises:
        InvalidParameterValueError: the value is too large (the message gives both sizes).
    """
    size = len(msgspec.msgpack.encode(value))
    if size > MAX_VALUE_BYTES:
        raise InvalidParameterValueError(
            f"parameter {where[:200]}: value is {size} bytes encoded; the limit is "
            f"{MAX_VALUE_BYTES} (put bulk data on a topic)"
        )


def flatten(name: str, value: Value) -> Iterator[tuple[str, Value]]:
    """The leaves a value sets at ``name``: a dict becomes one leaf per nested key.

    An empty dict is a leaf of its own (an empty namespace). Lists are leaves, even of dicts.

    Raises:
        InvalidNameError: a dict key is not a valid name segment.
    """
    if not isinstance(value, dict) or not value:
        yield name, value
        return
    for key, sub in value.items():
        if not _SEGMENT.match(key) or "__" in key:
            raise InvalidNameError(
                f"invalid parameter name segment {key!r} in the dict set at {name}: use a letter"
                " or '_' then letters, digits or '_' (no '__', '/' or '.')"
            )
        yield from flatten(join(name, key), sub)


def copy_value(value: Value) -> Value:
    """A copy the caller may mutate without touching the store."""
    return copy.deepcopy(value) if isinstance(value, (list, dict)) else value
