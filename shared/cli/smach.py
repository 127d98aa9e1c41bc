"""`zenros smach list|show|set_initial`: find running state machines, draw them, seed their start."""

from __future__ import annotations

import argparse
import json
import sys
import threading
from typing import Any

import zenoh
from zenoh import ext as zext

from ..codec import codec_for, to_builtins
from ..context import Context
from ..errors import CodecError
from ..names import resolve
from ..rpc import Client
from ..smach.introspection import (
    ContainerStatus,
    SetInitialState,
    SetInitialStateRequest,
    StateStructure,
)
from ..smach.render import render_tree
from .common import CliError, add_common, open_context, parse_yaml_arg

STRUCTURE_TYPE = codec_for(StateStructure).type_name
_CLEAR = "\x1b[H\x1b[2J"


def register(sub: Any) -> None:
    p = sub.add_parser("smach", help="state machines: list, show, set_initial")
    verbs = p.add_subparsers(dest="verb", required=True)
    verbs.add_parser("list", help="list the introspection servers of running machines")
    v = verbs.add_parser("show", help="print the live tree of a machine, active states marked *")
    v.add_argument("name", nargs="?", help="the server (default: the only one running)")
    v.add_argument("--once", action="store_true", help="print the tree once and exit")
    v.add_argument("--json", action="store_true", help="structure and status as one JSON line")
    v.add_argument("--timeout", type=float, default=10.0,
                   help="with --once: give up after N seconds (default 10)")
    v = verbs.add_parser("set_initial",
                         help="choose where a container starts next, and seed its userdata")
    v.add_argument("name", help="the server, e.g. /patrol/smach")
    v.add_argument("-s", "--state", action="append", default=[], dest="states",
                   metavar="LABEL", help="initial state label (repeatable; none: keep it)")
    v.add_argument("--path", default="/", help="the container, e.g. /PATROL (default: root)")
    v.add_argument("--userdata", default="{}", help="keys to set, YAML: '{laps: 2}'")
    v.add_argument("--timeout", type=float, default=5.0)
    for verb in verbs.choices.values():
        add_common(verb)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args, settle=args.verb == "list" or getattr(args, "name", None) is None)
    try:
        if args.verb == "list":
            return _list(ctx)
        if args.verb == "show":
            return _show(ctx, args)
        return _set_initial(ctx, args)
    finally:
        ctx.close()


def servers(ctx: Context) -> dict[str, list[str]]:
    """Introspection server name -> the nodes publishing its structure."""
    found: dict[str, list[str]] = {}
    for topic, types in ctx.graph.topics().items():
        if topic.endswith("/structure") and STRUCTURE_TYPE in types:
            nodes = sorted({t.node for t in ctx.graph.publishers(topic)})
            found[topic.removesuffix("/structure")] = nodes
    return found


def _list(ctx: Context) -> int:
    for name, nodes in servers(ctx).items():
        print(f"{name}  (node {', '.join(nodes) or '?'})")
    return 0


def _server_name(ctx: Context, name: str | None) -> str:
    if name is not None:
        return resolve(name)
    found = list(servers(ctx))
    if len(found) == 1:
        return found[0]
    if not found:
        raise CliError("no smach introspection server found; is a machine running with an"
                       " IntrospectionServer, under this --prefix?")
    raise CliError(f"several machines are running; name one of: {', '.join(found)}")


class _Latest:
    """The newest structure and status of one server, from latched subscriptions."""

    def __init__(self, ctx: Context, name: str) -> None:
        self.name = name
        self.structure: StateStructure | None = None
        self.status: ContainerStatus | None = None
        self.version = 0
        self._cond = threading.Condition()
        self._structure_codec = codec_for(StateStructure)
        self._status_codec = codec_for(ContainerStatus)
        self._subs = [self._subscribe(ctx, f"{name}/{part}", part)
                      for part in ("structure", "status")]

    def _subscribe(self, ctx: Context, topic: str, part: str) -> Any:
        def on_sample(sample: zenoh.Sample) -> None:
            self._on_sample(part, sample.payload.to_bytes())

        return zext.declare_advanced_subscriber(
            ctx.session, ctx.keys.topic(topic), on_sample,
            history=zext.HistoryConfig(detect_late_publishers=True, max_samples=1),
            recovery=zext.RecoveryConfig(heartbeat=True, periodic_queries=None),
            subscriber_detection=True,
        )

    def _on_sample(self, part: str, data: bytes) -> None:
        try:
            if part == "structure":
                structure = self._structure_codec.decode(data)
            else:
                status = self._status_codec.decode(data)
        except CodecError as exc:
            print(f"warning: bad {part} sample from {self.name}: {exc}", file=sys.stderr)
            return
        with self._cond:
            if part == "structure":
                self.structure = structure
            else:
                self.status = status
            self.version += 1
            self._cond.notify_all()

    def wait_newer(self, seen: int, timeout: float | None) -> int:
        """Block until both parts arrived and something changed since ``seen``; the version."""
        with self._cond:
            self._cond.wait_for(lambda: self.structure is not None and self.status is not None
                                and self.version != seen, timeout)
            return self.version

    def close(self) -> None:
        for sub in self._subs:
            sub.undeclare()


def _show(ctx: Context, args: argparse.Namespace) -> int:
    name = _server_name(ctx, args.name)
    latest = _Latest(ctx, name)
    try:
        if args.once:
            if latest.wait_newer(0, args.timeout) == 0 or latest.structure is None:
                raise CliError(f"no structure and status from {name} within {args.timeout:g} s;"
                               " see `zenros smach list`")
            _print(latest, args.json, clear=False)
            return 0
        seen, shown = 0, None
        clear = sys.stdout.isatty() and not args.json
        while True:  # redraw on change only: the status heartbeat repeats itself
            seen = latest.wait_newer(seen, 0.5)
            with latest._cond:
                now = (latest.structure, latest.status)
            if now[0] is not None and now != shown:
                _print(latest, args.json, clear=clear)
                shown = now
    except KeyboardInterrupt:
        return 0
    finally:
        latest.close()


def _print(latest: _Latest, as_json: bool, clear: bool) -> None:
    with latest._cond:
        structure, status = latest.structure, latest.status
    assert structure is not None
    if as_json:
        body = {"name": latest.name, "structure": to_builtins(structure),
                "status": to_builtins(status) if status is not None else None}
        sys.stdout.write(json.dumps(body) + "\n")
    else:
        text = render_tree(structure, status, title=latest.name)
        sys.stdout.write((_CLEAR if clear else "") + text + ("\n" if clear else "\n---\n"))
    sys.stdout.flush()


def _set_initial(ctx: Context, args: argparse.Namespace) -> int:
    name = resolve(args.name)
    userdata = parse_yaml_arg(args.userdata)
    client = Client(ctx, SetInitialState, f"{name}/set_initial_state")
    if not client.wait_for_service(args.timeout):
        raise CliError(f"no introspection server {name} (service {client.name} not found)")
    response = client.call(SetInitialStateRequest(path=args.path, initial_states=args.states,
                                                  userdata=userdata), timeout=args.timeout)
    if not response.success:
        raise CliError(response.message)
    print(response.message)
    return 0
