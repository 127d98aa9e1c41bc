"""`zenros param list|get|set|delete|dump|load`: the master's parameters (as ``rosparam``);
`zenros param describe NODE`: what a node declared (types, limits, descriptions)."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import yaml

from ..context import Context
from ..errors import ParameterError
from ..param_client import ParameterClient
from ..param_config import check_value, describe_constraints
from ..param_describe import fetch_descriptions
from ..param_protocol import local_param_name
from ..params import coerce
from .common import CliError, add_common, open_context, print_data


def register(sub: Any) -> None:
    p = sub.add_parser("param", help="parameters on master: list, get, set, delete, dump, "
                       "load; describe a node's declarations")
    verbs = p.add_subparsers(dest="verb", required=True)
    v = verbs.add_parser("list", help="list parameter names")
    v.add_argument("under", nargs="?", default="/", metavar="NAMESPACE",
                   help="a namespace (default /)")
    v = verbs.add_parser("get", help="print a value, or a namespace as a tree")
    v.add_argument("name")
    v.add_argument("--json", action="store_true", help="print JSON instead of YAML")
    v = verbs.add_parser("set", help="set a value (read as YAML: 0.5, true, '[1, 2]', '{a: 1}')")
    v.add_argument("name")
    v.add_argument("value")
    v.add_argument("--force", action="store_true",
                   help="store the value even if the owning node declared another type")
    v = verbs.add_parser("delete", help="delete a parameter (a namespace with --namespace)")
    v.add_argument("name")
    v.add_argument("--namespace", action="store_true",
                   help="delete a whole namespace (`--namespace /` deletes every parameter)")
    v = verbs.add_parser("dump", help="write parameters as a ROS 2 params file")
    v.add_argument("under", nargs="?", default="/", metavar="NAMESPACE",
                   help="a namespace (default /)")
    v.add_argument("-o", "--output", metavar="FILE", help="write to FILE (default stdout)")
    v = verbs.add_parser("load", help="set the parameters of a ROS 2 (or rosparam) YAML file")
    v.add_argument("file")
    v.add_argument("namespace", nargs="?", default="/", help="where names land (default /)")
    v = verbs.add_parser("describe", help="a node's declared parameters: type, limits, "
                         "read-only, description (asks the node, not master)")
    v.add_argument("node", help="the node's full name, e.g. /nav")
    v.add_argument("names", nargs="*", metavar="NAME", help="only these parameters")
    v.add_argument("--json", action="store_true", help="print JSON instead of a table")
    for verb in verbs.choices.values():
        add_common(verb)
        verb.add_argument("--timeout", type=float, default=5.0,
                          help="seconds to wait for master, or for the node (default 5)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args, settle=False, required=True)
    try:
        if args.verb == "describe":
            return _describe(ctx, args)
        client = ParameterClient(ctx, timeout=max(args.timeout, 1.0))
        if not client.wait_for_master(args.timeout):
            raise CliError(f"no master reachable within {args.timeout:g} s (prefix "
                           f"{ctx.keys.prefix!r}); start it with"
                           " `python -m zenros.services.master`")
        if args.verb == "set" and not args.force:
            _check_declared(ctx, client.resolve(args.name), _parse_value(args.value))
        return int(_VERBS[args.verb](client, args))
    finally:
        ctx.close()


def _list(client: ParameterClient, args: argparse.Namespace) -> int:
    for name in client.list(args.under):
        print(name)
    return 0


def _get(client: ParameterClient, args: argparse.Namespace) -> int:
    value = client.get(args.name)
    if args.json or not isinstance(value, dict):
        print_data(value, True)
    else:
        print_data(value, False, separator=False)
    return 0


def _describe(ctx: Context, args: argparse.Namespace) -> int:
    node = "/" + args.node.strip("/")
    deadline = time.monotonic() + args.timeout
    ctx.graph.settle(quiet=0.2, timeout=1.0)
    found = fetch_descriptions(ctx, node, timeout=0.5)
    while found is None and time.monotonic() < deadline:  # a new session learns routes late
        time.sleep(0.1)
        found = fetch_descriptions(ctx, node, timeout=0.5)
    if found is None:
        raise CliError(f"node {node} did not answer within {args.timeout:g} s (is it running? "
                       "`zenros node list` shows the nodes)")
    unknown = [n for n in args.names if n not in found]
    if unknown:
        raise CliError(f"{node} declares no parameter {', '.join(map(repr, unknown))}; it "
                       f"declares: {', '.join(sorted(found))}")
    chosen = {n: found[n] for n in sorted(args.names or found)}
    if args.json:
        print_data(chosen, True)
        return 0
    width = max(map(len, chosen), default=0)
    for name, d in chosen.items():
        limits = describe_constraints(d.get("constraints") or {})
        flags = ", ".join(x for x in (str(d.get("type")), limits,
                                      "read-only" if d.get("read_only") else "",
                                      "dynamic typing" if d.get("dynamic_typing") else "")
                          if x)
        text = str(d.get("description") or "")
        print(f"{name:<{width}}  {flags}" + (f"  -- {text}" if text else ""))
    return 0


def _parse_value(text: str) -> Any:
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise CliError(f"invalid YAML value {text!r}: {exc}") from exc


def _set(client: ParameterClient, args: argparse.Namespace) -> int:
    client.set(args.name, _parse_value(args.value))
    return 0


_TYPES = {"bool": bool, "int": int, "float": float, "str": str, "bytes": bytes, "list": list,
          "dict": dict}


def _check_declared(ctx: Context, full: str, value: Any) -> None:
    """Refuse a value the node owning ``full`` declared with another type (or read-only),
    as the node itself would; nodes that do not answer are not checked."""
    ctx.graph.settle(quiet=0.2, timeout=1.0)
    for node in ctx.graph.node_names():
        local = local_param_name(node, full)
        if local is None:
            continue
        declared = (fetch_descriptions(ctx, node) or {}).get(local)
        if not isinstance(declared, dict):
            continue
        kind = _TYPES.get(str(declared.get("type")))
        if declared.get("read_only"):
            raise CliError(f"{node} declared {local!r} read-only; --force stores {full} anyway")
        if kind is None:
            continue
        try:
            value = coerce(local, kind, value)
        except ParameterError:
            raise CliError(
                f"{node} declared {local!r} as {declared['type']}; {value!r} is "
                f"{type(value).__name__} (--force stores it anyway)"
            ) from None
        constraints = declared.get("constraints")
        why = check_value(value, constraints) if isinstance(constraints, dict) else None
        if why is not None:
            raise CliError(f"{node} refuses {local!r}: {why} (--force stores it anyway)")


def _delete(client: ParameterClient, args: argparse.Namespace) -> int:
    client.delete(args.name, namespace=args.namespace)
    return 0


def _dump(client: ParameterClient, args: argparse.Namespace) -> int:
    text = client.dump(args.under)
    if args.output:
        Path(args.output).write_text(text)
    else:
        sys.stdout.write(text)
    return 0


def _load(client: ParameterClient, args: argparse.Namespace) -> int:
    try:
        text = Path(args.file).read_text()
    except OSError as exc:
        raise CliError(f"cannot read {args.file}: {exc}") from exc
    names = client.load(text, args.namespace, source=args.file)
    print(f"loaded {len(names)} parameters from {args.file}")
    return 0


_VERBS = {"list": _list, "get": _get, "set": _set, "delete": _delete, "dump": _dump,
          "load": _load}

__all__ = ["register", "run"]
