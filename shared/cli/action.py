"""`zenros action list|info|send_goal|echo`."""

from __future__ import annotations

import argparse
import os
import sys
import threading
from typing import Any

from ..action import ActionClient, ClientGoalHandle, GoalResult, GoalStatus
from ..codec import from_builtins, to_builtins
from ..context import Context
from ..errors import ZenrosTimeout
from ..names import resolve
from .action_echo import echo
from .common import (
    STDOUT_CLOSED,
    CliError,
    ToolNode,
    add_common,
    check_graph_type,
    find_action_type,
    open_context,
    parse_yaml_arg,
    print_data,
    stdout_closed,
)


def register(sub: Any) -> None:
    p = sub.add_parser("action", help="actions: list, info, send_goal, echo")
    verbs = p.add_subparsers(dest="verb", required=True)
    v = verbs.add_parser("list", help="list actions")
    v.add_argument("-t", "--show-types", action="store_true")
    v = verbs.add_parser("info", help="the type and servers of an action")
    v.add_argument("action")
    v.add_argument("-t", "--show-types", action="store_true")
    v = verbs.add_parser("send_goal", help="send a goal and wait for its result")
    v.add_argument("action", help="action name, e.g. /fibonacci")
    v.add_argument("type", help="action type, e.g. example_interfaces/action/Fibonacci")
    v.add_argument("goal", nargs="?", default="{}", help="the goal in YAML, e.g. '{order: 5}'")
    v.add_argument("-f", "--feedback", action="store_true", help="print feedback")
    v.add_argument("--server-timeout", type=float, default=10.0,
                   help="seconds to wait for the action server, and for its answer to the "
                        "goal (default 10)")
    v.add_argument("--json", action="store_true", help="print messages as JSON lines")
    v = verbs.add_parser("echo", help="what an action's server handles: its services' "
                                      "introspection events, feedback and status "
                                      "(ros2 action echo)")
    v.add_argument("action")
    v.add_argument("--once", action="store_true", help="print one message and exit")
    v.add_argument("-n", "--count", type=int, default=0, help="exit after N messages")
    v.add_argument("--timeout", type=float, default=0.0,
                   help="give up after N seconds (exit code 1 if nothing came)")
    v.add_argument("--json", action="store_true", help="print messages as JSON lines")
    for verb in verbs.choices.values():
        add_common(verb)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args, settle=args.verb in ("list", "info"),
                       waiting_for=f"the action server {getattr(args, 'action', '')}")
    try:
        if args.verb == "list":
            return _list(ctx, args)
        if args.verb == "info":
            return _info(ctx, args)
        if args.verb == "echo":
            return echo(ctx, args)
        return _send_goal(ctx, args)
    finally:
        ctx.close()


def _list(ctx: Context, args: argparse.Namespace) -> int:
    for name, types in ctx.graph.actions().items():
        print(f"{name} [{', '.join(types)}]" if args.show_types else name)
    return 0


def _info(ctx: Context, args: argparse.Namespace) -> int:
    name = resolve(args.action, kind="action")
    actions = ctx.graph.actions()
    servers = ctx.graph.action_servers(name)
    clients = ctx.graph.action_clients(name)
    types = actions.get(name) or sorted({t.type for t in clients})
    if not types:
        raise CliError(f"unknown action {name}; known: {', '.join(actions) or 'none'}")
    print(f"Action: {name}")
    print(f"Type: {', '.join(types)}")
    for label, toks in (("Action clients", clients), ("Action servers", servers)):
        print(f"{label}: {len(toks)}")
        for t in sorted(toks, key=lambda t: t.node):
            print(f"    {t.node}" + (f" [{t.type}]" if args.show_types else ""))
    return 0


def _send_goal(ctx: Context, args: argparse.Namespace) -> int:
    action = find_action_type(args.type)
    goal = from_builtins(parse_yaml_arg(args.goal), action.Goal)
    name = resolve(args.action, kind="action")
    ctx.graph.settle(quiet=0.2, timeout=1.0)
    check_graph_type("action", name, action.name, ctx.graph.actions().get(name))
    node = ToolNode(f"zenros_action_send_goal_{os.getpid()}", context=ctx)
    try:
        # a goal no server answered is sent again while the graph lists one (zenros.reach)
        # and a server slow to answer it (a loaded fleet process) is waited for as long as
        # one slow to appear: ros2 action send_goal waits for the goal response unbounded
        client = ActionClient(node, action, name, reach_grace=args.server_timeout,
                              send_timeout=max(10.0, args.server_timeout))
        print("Waiting for an action server to become available...")
        if not client.wait_for_server(args.server_timeout):
            raise CliError(f"action server {client.name} is not available "
                           f"(waited {args.server_timeout:g} s)")
        _show("Sending goal:", to_builtins(goal), args.json)

        announced = threading.Event()

        def on_feedback(msg: Any) -> None:
            announced.wait(5.0)  # print "Goal accepted" first
            try:
                _show("Feedback:", to_builtins(msg.feedback), args.json)
            except BrokenPipeError:
                stdout_closed()

        handle = client.send_goal_async(goal, on_feedback if args.feedback else None)
        return _follow(handle, args.json, announced)
    finally:
        node.close()


def _follow(handle: ClientGoalHandle, as_json: bool, announced: threading.Event) -> int:
    try:
        if not handle.wait_accepted():
            print(f"Goal was rejected: {handle.reason}")
            return 1
        print(f"Goal accepted with ID: {handle.goal_id.hex}\n", flush=True)
        announced.set()
        outcome = _result(handle)
    except KeyboardInterrupt:
        with _OUT:
            print("Canceling goal...", flush=True)
        handle.cancel()
        outcome = handle.result(10.0)
        interrupted = True
    else:
        interrupted = False
    with _OUT:
        if outcome.status is GoalStatus.LOST:
            print(f"Goal lost: {outcome.reason}")
        else:
            print("Result:")
            _print(to_builtins(outcome.result), as_json)
        print(f"Goal finished with status: {outcome.status.name}", flush=True)
    return 0 if interrupted or outcome.status is GoalStatus.SUCCEEDED else 1


def _result(handle: ClientGoalHandle) -> GoalResult:
    """The goal's end; a closed stdout (``| head``) stops the wait as Ctrl-C does."""
    while not STDOUT_CLOSED.is_set():
        try:
            return handle.result(0.2)
        except ZenrosTimeout:
            continue
    raise KeyboardInterrupt


_OUT = threading.Lock()  # feedback prints from another thread: keep each block whole


def _show(header: str, data: Any, as_json: bool) -> None:
    with _OUT:
        print(header)
        _print(data, as_json)


def _print(data: Any, as_json: bool) -> None:
    print_data(data, as_json, separator=False)
    if not as_json:
        sys.stdout.write("\n")
    sys.stdout.flush()
