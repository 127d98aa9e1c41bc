"""Launch files: YAML into a `LaunchDescription` (args, nodes, includes, groups, namespaces)."""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import yaml

from ..errors import InvalidNameError, LaunchError
from ..names import Remapper, validate_node_name
from .args import check_value
from .context import Context
from .model import (
    ARG_TYPES,
    ArgDecl,
    ArgType,
    ComponentSpec,
    LaunchDescription,
    Output,
    ProcessSpec,
)
from .substitution import Scope, parse_bool, substitute, substitute_value

__all__ = ["declared_args", "load_launch"]

FILE_KEYS = ("args", "env", "nodes", "include", "group", "checks")
ARG_KEYS = ("default", "description", "type", "choices", "min", "above", "max")
CHECK_KEYS = ("fail_if", "error")
GROUP_KEYS = ("namespace", "env", "nodes", "include", "group", "if", "unless", "foreach")
INCLUDE_KEYS = ("file", "args", "namespace", "if", "unless", "foreach")
FOREACH_KEYS = ("var", "count", "start")
MAX_REPEATS = 1000
NODE_KEYS = (
    "name", "module", "exec", "cmd", "arguments", "namespace", "remap", "params", "env", "cwd",
    "respawn", "respawn_delay", "required", "output", "ros_args", "if", "unless", "container",
    "components",
)
COMPONENT_KEYS = ("plugin", "name", "namespace", "remap", "params", "if", "unless")
_PLUGIN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*:[A-Za-z_][A-Za-z0-9_]*\Z")
_MODULE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*\Z")


def load_launch(
    path: str | os.PathLike[str],
    args: Mapping[str, str] | None = None,
    environ: Mapping[str, str] | None = None,
) -> LaunchDescription:
    """Load a launch file and everything it includes.

    Args:
        path: the launch file.
        args: values for its declared arguments (the ``name:=value`` of the command line).
        environ: the environment seen by ``$(env ...)`` (default: ``os.environ``).

    Raises:
        LaunchError: the message names the file, the key path and what was expected.
    """
    out = LaunchDescription()
    env = dict(os.environ if environ is None else environ)
    root = Path(path).resolve()
    if not root.is_file():
        raise LaunchError(f"launch file not found: {path}")
    ctx = _load_file(root, dict(args or {}), Context(Scope(root, environ=env)), out, top=True)
    out.args = dict(ctx.scope.args)
    seen: dict[str, str] = {}  # node FQN: where it was declared
    for spec in out.processes:
        for fqn in (spec.fqn, *(c.fqn for c in spec.components)):
            if fqn in seen:
                raise LaunchError(
                    f"two nodes are named {fqn}: {seen[fqn]} and {spec.origin};"
                    " give one a different name or namespace"
                )
            seen[fqn] = spec.origin
    return out


def declared_args(path: str | os.PathLike[str]) -> list[ArgDecl]:
    """The arguments a launch file declares (for ``--show-args``), without loading it."""
    file = Path(path).resolve()
    return _declarations(_read(file, Context(Scope(file))), Context(Scope(file)))


def _read(file: Path, ctx: Context) -> dict[str, Any]:
    try:
        doc = yaml.safe_load(file.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as exc:
        raise ctx.fail("", f"cannot read launch file: {exc}") from exc
    doc = ctx.mapping(doc, "top level")
    ctx.keys(doc, FILE_KEYS, "")
    return doc


def _declarations(doc: dict[str, Any], ctx: Context) -> list[ArgDecl]:
    decls = []
    for name, spec in ctx.mapping(doc.get("args"), "args").items():
        where = f"args.{name}"
        if spec is None or isinstance(spec, (str, int, float, bool)):
            decls.append(ArgDecl(name, _scalar(spec)))
            continue
        spec = ctx.mapping(spec, where)
        ctx.keys(spec, ARG_KEYS, where)
        kind = str(spec.get("type", "str"))
        if kind not in ARG_TYPES:
            raise ctx.fail(f"{where}.type", f"expected one of {', '.join(ARG_TYPES)}, got {kind!r}")
        choices = ctx.items(spec.get("choices"), f"{where}.choices")
        decls.append(ArgDecl(
            name, _scalar(spec.get("default")), str(spec.get("description", "")),
            type=_arg_type(kind),
            choices=tuple(str(_scalar(c)) for c in choices),
            min=_bound(spec, "min", ctx, where),
            above=_bound(spec, "above", ctx, where),
            max=_bound(spec, "max", ctx, where),
        ))
    return decls


def _arg_type(kind: str) -> ArgType:
    for t in ARG_TYPES:
        if t == kind:
            return t
    return "str"


def _bound(spec: dict[str, Any], key: str, ctx: Context, where: str) -> float | None:
    raw = spec.get(key)
    if raw is None:
        return None
    if isinstance(raw, bool) or not isinstance(raw, (int, float)):
        raise ctx.fail(f"{where}.{key}", f"expected a number, got {raw!r}")
    return float(raw)


def _checked(decl: ArgDecl, value: str, given: bool, ctx: Context) -> str:
    """The value checked against its declaration; the error names ``name:=value``."""
    try:
        return check_value(decl, value)
    except ValueError as exc:
        where = f"{decl.name}:={value}" if given else f"args.{decl.name} (default {value!r})"
        raise ctx.fail(where, str(exc)) from exc


def _checks(raw: Any, ctx: Context) -> None:
    """The file's ``checks``: the first whose ``fail_if`` is true stops the launch with its
    ``error`` (after substitution), e.g. a combination of arguments that cannot work."""
    for i, item in enumerate(ctx.items(raw, "checks")):
        where = f"checks[{i}]"
        entry = ctx.mapping(item, where)
        ctx.keys(entry, CHECK_KEYS, where)
        if "fail_if" not in entry or "error" not in entry:
            raise ctx.fail(where, "a check needs fail_if and error")
        if parse_bool(entry["fail_if"], ctx.scope, f"{where}.fail_if"):
            raise ctx.fail("", ctx.text(entry["error"], f"{where}.error"))


def _scalar(raw: Any) -> str | None:
    """An argument default as text (YAML ``true`` becomes ``true``, not ``True``)."""
    if raw is None:
        return None
    return str(raw).lower() if isinstance(raw, bool) else str(raw)


def _load_file(
    file: Path, given: dict[str, str], parent: Context, out: LaunchDescription, top: bool = False
) -> Context:
    if file in parent.stack:
        chain = " -> ".join(str(p) for p in (*parent.stack, file))
        raise LaunchError(f"include cycle: {chain}")
    ctx = replace(parent, scope=Scope(file, {}, parent.scope.environ), stack=(*parent.stack, file))
    out.files.append(str(file))
    doc = _read(file, ctx)
    decls = _declarations(doc, ctx)
    names = [d.name for d in decls]
    unknown = [k for k in given if k not in names]
    if unknown:
        known = ", ".join(names) or "none"
        raise ctx.fail("args", f"unknown argument {unknown[0]!r}; declared: {known}")
    values: dict[str, str] = {}
    for d in decls:
        if d.name in given:
            values[d.name] = _checked(d, given[d.name], True, ctx)
        elif d.default is not None:
            scope = Scope(file, values, ctx.scope.environ)
            default = substitute(d.default, scope, f"args.{d.name}")
            values[d.name] = _checked(d, default, False, ctx)
        else:
            why = f"argument {d.name!r} is required; pass {d.name}:=VALUE"
            raise ctx.fail(f"args.{d.name}", why)
    ctx.scope = Scope(file, values, ctx.scope.environ)
    if top:
        out.declared = decls
    _checks(doc.get("checks"), ctx)
    if "env" in doc:
        ctx.env = ctx.environment(doc["env"], "env")
    _body(doc, ctx, out, "")
    return ctx


def _body(doc: dict[str, Any], ctx: Context, out: LaunchDescription, where: str) -> None:
    """The ``nodes``, ``include`` and ``group`` keys, in the order they appear."""
    for key, raw in doc.items():
        prefix = f"{where}{key}"
        if key == "nodes":
            for i, node in enumerate(ctx.items(raw, prefix)):
                spec = _node(node, ctx, f"{prefix}[{i}]")
                if spec is not None:
                    out.processes.append(spec)
        elif key == "include":
            for i, inc in enumerate(ctx.items(raw, prefix)):
                _include(inc, ctx, out, f"{prefix}[{i}]")
        elif key == "group":
            for i, group in enumerate(ctx.items(raw, prefix)):
                _group(group, ctx, out, f"{prefix}[{i}]")


def _repeats(entry: dict[str, Any], ctx: Context, where: str) -> list[Context]:
    """The contexts an entry is loaded in: itself, or one per value of its ``foreach``
    variable (``{var: k, count: N, start: 1}``: ``$(arg k)`` is start .. start + N - 1 in the
    entry's own keys, as for N robots each in its own namespace)."""
    if "foreach" not in entry:
        return [ctx]
    at = f"{where}.foreach"
    spec = ctx.mapping(entry["foreach"], at)
    ctx.keys(spec, FOREACH_KEYS, at)
    if "var" not in spec or "count" not in spec:
        raise ctx.fail(at, "foreach needs var and count")
    var = ctx.text(spec["var"], f"{at}.var")
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", var):
        raise ctx.fail(f"{at}.var", f"{var!r} is not a name")
    if var in ctx.scope.args:
        raise ctx.fail(f"{at}.var", f"{var!r} is already an argument of this file")
    count, start = (_whole_number(spec.get(k, d), ctx, f"{at}.{k}") for k, d in
                    (("count", None), ("start", 1)))
    if not 0 <= count <= MAX_REPEATS:
        raise ctx.fail(f"{at}.count", f"expected 0 to {MAX_REPEATS}, got {count}")
    return [replace(ctx, scope=Scope(ctx.scope.file, {**ctx.scope.args, var: str(i)},
                                     ctx.scope.environ))
            for i in range(start, start + count)]


def _whole_number(raw: Any, ctx: Context, where: str) -> int:
    text = ctx.text(raw, where)
    try:
        return int(text)
    except ValueError:
        raise ctx.fail(where, f"expected a whole number, got {text!r}") from None


def _group(raw: Any, ctx: Context, out: LaunchDescription, where: str) -> None:
    entry = ctx.mapping(raw, where)
    ctx.keys(entry, GROUP_KEYS, where)
    for each in _repeats(entry, ctx, where):
        _group_once(entry, each, out, where)


def _group_once(entry: dict[str, Any], ctx: Context, out: LaunchDescription,
                where: str) -> None:
    if not ctx.enabled(entry, where):
        return
    inner = replace(ctx)
    if "namespace" in entry:
        inner.namespace = ctx.namespace_for(entry["namespace"], f"{where}.namespace")
    if "env" in entry:
        inner.env = ctx.environment(entry["env"], f"{where}.env")
    _body(entry, inner, out, f"{where}.")


def _include(raw: Any, ctx: Context, out: LaunchDescription, where: str) -> None:
    entry = {"file": raw} if isinstance(raw, str) else ctx.mapping(raw, where)
    ctx.keys(entry, INCLUDE_KEYS, where)
    if "file" not in entry:
        raise ctx.fail(where, "an include needs 'file'")
    for each in _repeats(entry, ctx, where):
        _include_once(entry, each, out, where)


def _include_once(entry: dict[str, Any], ctx: Context, out: LaunchDescription,
                  where: str) -> None:
    if not ctx.enabled(entry, where):
        return
    file = ctx.path(entry["file"], f"{where}.file").resolve()
    args = {
        k: ctx.text(v, f"{where}.args.{k}")
        for k, v in ctx.mapping(entry.get("args"), f"{where}.args").items()
    }
    inner = replace(ctx)
    if "namespace" in entry:
        inner.namespace = ctx.namespace_for(entry["namespace"], f"{where}.namespace")
    try:
        _load_file(file, args, inner, out)
    except LaunchError as exc:
        raise LaunchError(f"{exc}\n  while including it from {ctx.scope.file}: {where}") from exc


def _node(raw: Any, ctx: Context, where: str) -> ProcessSpec | None:
    entry = ctx.mapping(raw, where)
    ctx.keys(entry, NODE_KEYS, where)
    if not ctx.enabled(entry, where):
        return None
    kinds = [k for k in ("module", "exec", "cmd", "container") if k in entry]
    if len(kinds) != 1:
        raise ctx.fail(where, "give exactly one of module, exec, cmd or container")
    kind = kinds[0]
    if ("components" in entry) != (kind == "container"):
        raise ctx.fail(where, "a container needs components, and only a container has them")
    if kind == "container":
        cmd, default_name = [sys.executable, "-m", "zenros.container"], "container"
        if "name" not in entry:
            entry = {**entry, "name": entry["container"]}
    elif kind == "module":
        module = ctx.text(entry["module"], f"{where}.module")
        if not _MODULE.match(module):
            raise ctx.fail(f"{where}.module", f"{module!r} is not a dotted module name")
        cmd, default_name = [sys.executable, "-m", module], module.rsplit(".", 1)[-1]
    elif kind == "exec":
        cmd = [ctx.text(entry["exec"], f"{where}.exec")]
        default_name = Path(cmd[0]).name
    else:
        cmd = ctx.words(entry["cmd"], f"{where}.cmd")
        if not cmd:
            raise ctx.fail(f"{where}.cmd", "the command is empty")
        default_name = Path(cmd[0]).name
    name = ctx.text(entry["name"], f"{where}.name") if "name" in entry else _as_name(default_name)
    try:
        validate_node_name(name)
    except InvalidNameError as exc:
        raise ctx.fail(f"{where}.name", str(exc)) from exc
    ros_args = parse_bool(entry.get("ros_args", kind != "cmd"), ctx.scope, f"{where}.ros_args")
    remaps = _remaps(entry.get("remap"), ctx, f"{where}.remap")
    params = _params(entry.get("params"), ctx, f"{where}.params")
    if not ros_args and (remaps or params):
        raise ctx.fail(where, "remap and params need ros_args: true (cmd nodes get no ROS flags)")
    respawn = parse_bool(entry.get("respawn", False), ctx.scope, f"{where}.respawn")
    required = parse_bool(entry.get("required", False), ctx.scope, f"{where}.required")
    output = ctx.text(entry.get("output", "screen"), f"{where}.output")
    if output not in ("screen", "log"):
        raise ctx.fail(f"{where}.output", f"expected screen or log, got {output!r}")
    out_kind: Output = "screen" if output == "screen" else "log"
    namespace = (ctx.namespace_for(entry["namespace"], f"{where}.namespace")
                 if "namespace" in entry else ctx.namespace)
    components: tuple[ComponentSpec, ...] = ()
    if kind == "container":
        inner = replace(ctx, namespace=namespace)
        components = tuple(c for i, raw in enumerate(ctx.items(entry["components"],
                                                               f"{where}.components"))
                           if (c := _component(raw, inner, f"{where}.components[{i}]")))
        if not components:
            raise ctx.fail(f"{where}.components", "a container needs at least one component")
    return ProcessSpec(
        name=name,
        cmd=tuple(cmd),
        namespace=namespace,
        ros_args=ros_args,
        remaps=remaps,
        params=params,
        arguments=tuple(ctx.words(entry.get("arguments", []), f"{where}.arguments")),
        env=ctx.environment(entry.get("env"), f"{where}.env"),
        cwd=str(ctx.path(entry["cwd"], f"{where}.cwd")) if "cwd" in entry else None,
        respawn=respawn,
        respawn_delay=_delay(entry.get("respawn_delay", 0.0), ctx, f"{where}.respawn_delay"),
        required=required,
        output=out_kind,
        origin=f"{ctx.scope.file}: {where}",
        components=components,
    )


def _component(raw: Any, ctx: Context, where: str) -> ComponentSpec | None:
    """One ``components`` entry of a container: a node class run inside its process."""
    entry = ctx.mapping(raw, where)
    ctx.keys(entry, COMPONENT_KEYS, where)
    if not ctx.enabled(entry, where):
        return None
    for key in ("plugin", "name"):
        if key not in entry:
            raise ctx.fail(where, f"a component needs {key!r}")
    plugin = ctx.text(entry["plugin"], f"{where}.plugin")
    if not _PLUGIN.match(plugin):
        raise ctx.fail(f"{where}.plugin", f"{plugin!r} is not package.module:Class")
    name = ctx.text(entry["name"], f"{where}.name")
    try:
        validate_node_name(name)
    except InvalidNameError as exc:
        raise ctx.fail(f"{where}.name", str(exc)) from exc
    return ComponentSpec(
        plugin=plugin, name=name,
        namespace=(ctx.namespace_for(entry["namespace"], f"{where}.namespace")
                   if "namespace" in entry else ctx.namespace),
        remaps=_remaps(entry.get("remap"), ctx, f"{where}.remap"),
        params=_params(entry.get("params"), ctx, f"{where}.params"),
    )


def _as_name(text: str) -> str:
    name = re.sub(r"[^A-Za-z0-9_]", "_", text.removesuffix(".py"))
    return f"_{name}" if not name or name[0].isdigit() else name


def _remaps(raw: Any, ctx: Context, where: str) -> tuple[tuple[str, str], ...]:
    if isinstance(raw, dict):
        rules = [f"{ctx.text(k, where)}:={ctx.text(v, f'{where}.{k}')}" for k, v in raw.items()]
    else:
        rules = [ctx.text(r, f"{where}[{i}]") for i, r in enumerate(ctx.items(raw, where))]
    try:
        Remapper.parse(rules)
    except InvalidNameError as exc:
        raise ctx.fail(where, str(exc)) from exc
    return tuple((src, dst) for src, _, dst in (r.partition(":=") for r in rules))


def _params(raw: Any, ctx: Context, where: str) -> tuple[dict[str, Any] | str, ...]:
    items = raw if isinstance(raw, list) else [] if raw is None else [raw]
    out: list[dict[str, Any] | str] = []
    for i, item in enumerate(items):
        at = f"{where}[{i}]" if isinstance(raw, list) else where
        if isinstance(item, dict):
            out.append(substitute_value(ctx.mapping(item, at), ctx.scope, at))
        elif isinstance(item, str):
            out.append(str(ctx.path(item, at)))
        else:
            raise ctx.fail(at, f"expected a mapping of parameters or a params file, got {item!r}")
    return tuple(out)


def _delay(raw: Any, ctx: Context, where: str) -> float:
    text = ctx.text(raw, where)
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value >= 0:
        raise ctx.fail(where, f"expected a number of seconds >= 0, got {raw!r}")
    return value
