"""`zenros service list|type|call`."""

from __future__ import annotations

import argparse
from typing import Any

from ..codec import from_builtins, to_builtins
from ..names import resolve
from ..rpc import Client
from .common import (
    CliError,
    add_common,
    check_graph_type,
    find_service_type,
    open_context,
    parse_yaml_arg,
    print_data,
)


def register(sub: Any) -> None:
    p = sub.add_parser("service", help="services: list, type, call")
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
