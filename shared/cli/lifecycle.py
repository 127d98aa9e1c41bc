"""`zenros lifecycle nodes|get|set|list`: ros2 lifecycle's verbs over a managed node's
services (docs/lifecycle.md)."""

from __future__ import annotations

import argparse
from typing import Any

from ..msgs.lifecycle_msgs import (
    ChangeState,
    ChangeStateRequest,
    GetAvailableTransitions,
    GetAvailableTransitionsRequest,
    GetState,
    GetStateRequest,
    TransitionDescription,
)
from ..names import resolve
from ..rpc import Client
from .common import CliError, add_common, open_context

_GET_STATE = "lifecycle_msgs/GetState"


def register(sub: Any) -> None:
    p = sub.add_parser("lifecycle", help="managed nodes: nodes, get, set, list")
    verbs = p.add_subparsers(dest="verb", required=True)
    verbs.add_parser("nodes", help="list the managed (lifecycle) nodes")
    v = verbs.add_parser("get", help="a managed node's state (every one's without a name)")
    v.add_argument("node", nargs="?")
    v = verbs.add_parser("set", help="run a transition (label or id) on a managed node")
    v.add_argument("node")
    v.add_argument("transition", help="configure, activate, deactivate, cleanup, shutdown "
                   "or the id")
    v = verbs.add_parser("list", help="the transitions available from a node's state")
    v.add_argument("node")
    v.add_argument("-a", "--all", action="store_true", help="the whole transition graph")
    for verb in verbs.choices.values():
        verb.add_argument("--timeout", type=float, default=5.0, help="seconds per call")
        add_common(verb)
    p.set_defaults(func=run)


def _managed_nodes(ctx: Any) -> list[str]:
    out = []
    for name, types in ctx.graph.services().items():
        if name.endswith("/get_state") and _GET_STATE in types:
            out.append(name.removesuffix("/get_state"))
    return sorted(out)


def _call(ctx: Any, srv: Any, name: str, request: Any, timeout: float) -> Any:
    client = Client(ctx, srv, name)
    try:
        if not client.wait_for_service(timeout):
            raise CliError(f"{name} is not available: is the node a lifecycle node?")
        return client.call(request, timeout=timeout)
    finally:
        client.close()


def _state(ctx: Any, node: str, timeout: float) -> str:
    s = _call(ctx, GetState, f"{node}/get_state", GetStateRequest(), timeout).current_state
    return f"{s.label} [{s.id}]"


def _transitions(ctx: Any, node: str, service: str,
                 timeout: float) -> list[TransitionDescription]:
    res = _call(ctx, GetAvailableTransitions, f"{node}/{service}",
                GetAvailableTransitionsRequest(), timeout)
    return list(res.available_transitions)


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args)
    try:
        if args.verb == "nodes":
            for n in _managed_nodes(ctx):
                print(n)
            return 0
        if args.verb == "get" and args.node is None:
            for n in _managed_nodes(ctx):
                print(f"{n}: {_state(ctx, n, args.timeout)}")
            return 0
        node = resolve(args.node, kind="node")
        if args.verb == "get":
            print(_state(ctx, node, args.timeout))
            return 0
        if args.verb == "list":
            service = "get_transition_graph" if args.all else "get_available_transitions"
            for t in _transitions(ctx, node, service, args.timeout):
                print(f"- {t.transition.label} [{t.transition.id}]\n"
                      f"\tStart: {t.start_state.label}\n\tGoal: {t.goal_state.label}")
            return 0
        return _set(ctx, node, args.transition, args.timeout)
    finally:
        ctx.close()


def _set(ctx: Any, node: str, wanted: str, timeout: float) -> int:
    available = _transitions(ctx, node, "get_available_transitions", timeout)
    chosen = next((t.transition for t in available
                   if wanted in (t.transition.label, str(t.transition.id))), None)
    if chosen is None:
        listed = "".join(f"\n- {t.transition.label} [{t.transition.id}]" for t in available)
        raise CliError(f"unknown transition {wanted!r} from the node's state; available "
                       f"ones are:{listed or ' none'}")
    res = _call(ctx, ChangeState, f"{node}/change_state",
                ChangeStateRequest(transition=chosen), timeout)
    if not res.success:
        print("Transitioning failed")
        return 1
    print("Transitioning successful")
    return 0
