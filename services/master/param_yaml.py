"""Parameters as YAML, in the ROS 2 params-file layout (``node: {ros__parameters: {...}}``)."""

from __future__ import annotations

import itertools
import re
from typing import Any

import yaml
from zenros.errors import InvalidNameError, ParameterError
from zenros.names import basename, join, namespace_of, validate_namespace

from .param_value import Value, canonical, check_value

__all__ = ["ROS_PARAMETERS", "dump_yaml", "parse_yaml"]

ROS_PARAMETERS = "ros__parameters"
_WILDCARDS = ("/**", "**")
_SEGMENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def dump_yaml(view: Value, prefix: str) -> str:
    """Render what the store holds at ``prefix`` in the ROS 2 layout.

    A namespace ``/nav`` becomes one block ``/nav: {ros__parameters: {...}}``; the root becomes
    one block per top-level namespace plus a ``/**`` block for top-level leaves; a single leaf
    becomes a block for its parent namespace holding just that leaf. `parse_yaml` reads every
    form back to the same names.

    Args:
        view: the value of ``store.get(prefix)`` (a leaf value or a nested dict).
        prefix: the absolute name that was read.
    """
    prefix = canonical(prefix)
    blocks: dict[str, Any] = {}
    if isinstance(view, dict) and prefix == "/":
        top = {k: v for k, v in view.items() if not isinstance(v, dict)}
        if top:
            blocks[_WILDCARDS[0]] = {ROS_PARAMETERS: top}
        for key, sub in view.items():
            if isinstance(sub, dict):
                blocks["/" + key] = {ROS_PARAMETERS: sub}
    elif isinstance(view, dict):
        blocks[prefix] = {ROS_PARAMETERS: view}
    else:
        parent = namespace_of(prefix)
        blocks[_WILDCARDS[0] if parent == "/" else parent] = {
            ROS_PARAMETERS: {basename(prefix): view}
        }
    text: str = yaml.safe_dump(blocks, sort_keys=False, allow_unicode=True)
    return text


def parse_yaml(text: str, namespace: str = "/", source: str = "<string>") -> dict[str, Value]:
    """Flatten a params document into absolute leaf names and their values.

    The ROS 2 layout is read: top-level keys are node names (``nav``, ``/robot1/nav``, or
    nested namespaces ``robot1: {nav: {ros__parameters: ...}}``), each relative to
    ``namespace`` (a leading ``/`` too); ``/**`` stands for ``namespace`` itself. Under
    ``ros__parameters``, nested dicts and dotted keys (``costmap.inflation``) are namespaces.
    A document without any ``ros__parameters`` is read as a plain tree (``rosparam`` layout).

    Args:
        text: the YAML document.
        namespace: where the document's names land.
        source: the file name, for error messages.

    Raises:
        ParameterError: bad YAML, a bad layout, name or value, each naming ``source``.
    """
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ParameterError(f"{source}: not valid YAML: {exc}") from exc
    if doc is None:
        return {}
    if not isinstance(doc, dict):
        raise ParameterError(
            f"{source}: expected a mapping of node names at the top, got {type(doc).__name__}"
        )
    try:
        ns = validate_namespace(namespace)
    except InvalidNameError as exc:
        raise ParameterError(f"{source}: {exc}") from exc
    out: dict[str, Value] = {}
    if _has_ros_parameters(doc):
        _walk(doc, ns, out, source)
    else:
        _params(doc, ns, out, source)
    return _without_overlaps(out, source)


def _without_overlaps(out: dict[str, Value], source: str) -> dict[str, Value]:
    """Drop empty namespaces that got content; refuse a name that is both value and namespace."""
    names = sorted(out)
    for name, below in itertools.pairwise(names):
        if below.startswith(name + "/"):
            if out[name] != {}:
                raise ParameterError(
                    f"{source}: {name} is given both a value ({out[name]!r}) and, as a"
                    f" namespace, {below}"
                )
            del out[name]
    return out


def _has_ros_parameters(node: object) -> bool:
    if not isinstance(node, dict):
        return False
    return ROS_PARAMETERS in node or any(_has_ros_parameters(v) for v in node.values())


def _walk(mapping: dict[Any, Any], ns: str, out: dict[str, Value], source: str) -> None:
    for key, val in mapping.items():
        if key == ROS_PARAMETERS:
            if val is None or val == {}:
                if ns != "/":
                    out[ns] = {}
                continue
            if not isinstance(val, dict):
                raise ParameterError(
                    f"{source}: {ns}: {ROS_PARAMETERS} must be a mapping, got {type(val).__name__}"
                )
            _params(val, ns, out, source)
            continue
        sub = _node_namespace(key, ns, source)
        if not _has_ros_parameters(val):
            raise ParameterError(
                f"{source}: key {key!r} (under {ns}) has no {ROS_PARAMETERS} below it; in the"
                f" ROS 2 layout every parameter sits under '<node>: {{{ROS_PARAMETERS}: ...}}'"
            )
        _walk(val, sub, out, source)


def _node_namespace(key: object, ns: str, source: str) -> str:
    if not isinstance(key, str):
        raise ParameterError(f"{source}: node name {key!r} under {ns} is not a string")
    if key in _WILDCARDS:
        return ns
    if "*" in key:
        raise ParameterError(
            f"{source}: node pattern {key!r} is not supported here; use a node name or '/**'"
        )
    for part in key.strip("/").split("/"):
        ns = join(ns, _segment(part, key, ns, source))
    return ns


def _params(mapping: dict[Any, Any], ns: str, out: dict[str, Value], source: str) -> None:
    for key, val in mapping.items():
        if not isinstance(key, str):
            raise ParameterError(f"{source}: parameter key {key!r} under {ns} is not a string")
        name = ns
        for part in key.split("."):
            name = join(name, _segment(part, key, ns, source))
        if isinstance(val, dict) and val:
            _params(val, name, out, source)
            continue
        try:
            out[name] = check_value(val, name)
        except ParameterError as exc:
            raise type(exc)(f"{source}: {exc}") from exc


def _segment(part: str, key: str, ns: str, source: str) -> str:
    if not _SEGMENT.match(part) or "__" in part:
        raise ParameterError(
            f"{source}: invalid name {key!r} under {ns}: segment {part!r} must be a letter or '_'"
            " then letters, digits or '_' (no '__')"
        )
    return part
