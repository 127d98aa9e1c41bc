"""`zenros service list|type|call|echo`."""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

from ..codec import from_builtins, to_builtins
from ..names import resolve
from ..rpc import Client
from ..service_events import EVENT_SUFFIX, event_type_of
from .common import (
    CliError,
    Echo,
    ToolNode,
    add_common,
    check_graph_type,
    find_service_type,
    open_context,
    parse_yaml_arg,
    print_data,
)


def register(sub: Any) -> None:
    p = sub.add_parser("service", help="services: list, type, call, echo")
    verbs = p.add_subparsers(dest="verb", required=True)
    v = verbs.add_parser("list", help="list services")
    v.add_argument("-t", "--show-types", action="store_true")
    v = verbs.add_parser("type", help="the type of a service")
    v.add_argument("service")
    v = verbs.add_parser("call", help="call a service")
    v.add_argument("service")
    v.add_argument("type")
    v.add_argument("values", nargs="?", default="{}")
    v.add_argument("--timeout", type=float, default=5.0)
    v.add_argument("--json", action="store_true")
    v = verbs.add_parser("echo", help="a service's requests and responses, from its "
                                      "introspection events (ros2 service echo)")
    v.add_argument("service")
    v.add_argument("--once", action="store_true", help="print one event and exit")
    v.add_argument("-n", "--count", type=int, default=0, help="exit after N events")
    v.add_argument("--timeout", type=float, default=0.0,
                   help="give up after N seconds (exit code 1 if none came)")
    v.add_argument("--json", action="store_true")
    for verb in verbs.choices.values():
        add_common(verb)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args)
    try:
        if args.verb == "list":
            for name, types in ctx.graph.services().items():
                print(f"{name} [{', '.join(types)}]" if args.show_types else name)
            return 0
        name = resolve(args.service, kind="service")
        if args.verb == "type":
            found = ctx.graph.services().get(name)
            if not found:
                raise CliError(f"unknown service {name}")
            print("\n".join(found))
            return 0
        if args.verb == "echo":
            return _echo(ctx, name, args)
        srv = find_service_type(args.type)
        check_graph_type("service", name, srv.name, ctx.graph.services().get(name))
        request = from_builtins(parse_yaml_arg(args.values), srv.Request)
        client = Client(ctx, srv, name)
        if not client.wait_for_service(min(args.timeout, 5.0)):
            raise CliError(f"service {name} is not available")
        print(f"requester: making request: {request}")
        response = client.call(request, timeout=args.timeout, grace=args.timeout)
        print("response:")
        print_data(to_builtins(response), args.json, separator=False)
        return 0
    finally:
        ctx.close()


def _echo(ctx: Any, name: str, args: argparse.Namespace) -> int:
    """Print the events on ``<name>/_service_event`` as they come: each server and client
    of the service publishes them once its introspection is on (METADATA or CONTENTS)."""
    ctx.graph.settle(quiet=0.2, timeout=1.0)
    types = ctx.graph.services().get(name) or sorted(
        {t.type for t in ctx.graph.clients(name)})
    if not types:
        raise CliError(f"unknown service {name}: `zenros service list` names them")
    events_cls = event_type_of(find_service_type(types[0]))
    echo = Echo(1 if args.once else args.count, args.json)
    node = ToolNode(f"zenros_service_echo_{os.getpid()}", context=ctx)
    try:
        node.create_subscription(events_cls, name + EVENT_SUFFIX,
                                 lambda msg: echo.print(to_builtins(msg)))
        if not ctx.graph.publishers(name + EVENT_SUFFIX):
            sys.stderr.write(f"waiting for events of {name} (its server or a client must "
                             "turn introspection on: configure_introspection)\n")
            sys.stderr.flush()
        ended = echo.wait(args.timeout)
    finally:
        node.close()
    if not ended and args.timeout and not echo.count:
        raise CliError(f"no event of {name} within {args.timeout:g} s (is its introspection "
                       "on?)")
    return 0
