"""`zenros action echo ACTION`: what an action's server handles, as ``ros2 action echo``
(Kilted) shows it: the requests and responses of its three services from their
introspection events (the server must turn introspection on: `configure_introspection`),
with its feedback and status as they are published. Each message comes with the interface
it belongs to: GOAL_SERVICE, CANCEL_SERVICE, RESULT_SERVICE, FEEDBACK_TOPIC, STATUS_TOPIC."""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

import zenoh

from ..action.introspection import PARTS, action_service_types, part_name
from ..action.transport import status_subscriber
from ..action.types import GoalStatusArray
from ..action.wire import wire_types
from ..codec import codec_for, to_builtins
from ..context import Context
from ..errors import CodecError
from ..names import resolve
from ..service_events import EVENT_SUFFIX, event_type_of
from .common import CliError, Echo, ToolNode, find_action_type

__all__ = ["echo"]

_INTERFACES = {"send_goal": "GOAL_SERVICE", "cancel_goal": "CANCEL_SERVICE",
               "get_result": "RESULT_SERVICE"}


def echo(ctx: Context, args: argparse.Namespace) -> int:
    name = resolve(args.action, kind="action")
    ctx.graph.settle(quiet=0.2, timeout=2.0)
    types = ctx.graph.actions().get(name) or sorted(
        {t.type for t in ctx.graph.action_clients(name)})
    if not types:
        raise CliError(f"unknown action {name}: `zenros action list` names them")
    action = find_action_type(types[0])
    echo = Echo(1 if args.once else args.count, args.json)

    def show(interface: str, data: Any) -> None:
        echo.print({"interface": interface, **data})

    node = ToolNode(f"zenros_action_echo_{os.getpid()}", context=ctx)
    raw: list[Any] = []
    try:
        services = action_service_types(action)
        feedback = codec_for(wire_types(action).FeedbackMessage)
        status = codec_for(GoalStatusArray)

        def on(interface: str, codec: Any) -> Any:
            def callback(sample: zenoh.Sample) -> None:
                try:
                    msg = codec.decode(sample.payload.to_bytes())
                except CodecError as exc:
                    sys.stderr.write(f"{interface}: undecodable sample: {exc}\n")
                    return
                show(interface, to_builtins(msg))
            return callback

        raw.append(ctx.session.declare_subscriber(ctx.keys.action(name, "feedback"),
                                                  on("FEEDBACK_TOPIC", feedback)))
        raw.append(status_subscriber(ctx.session, ctx.keys.action(name, "status"),
                                     on("STATUS_TOPIC", status)))
        # the events' subscriptions last: once a server sees them matched, feedback and
        # status are subscribed too (declared earlier on the same session)
        def event_shower(interface: str) -> Any:
            return lambda msg: show(interface, to_builtins(msg))  # one argument: the message

        for part in PARTS:
            node.create_subscription(event_type_of(services[part]),
                                     part_name(name, part) + EVENT_SUFFIX,
                                     event_shower(_INTERFACES[part]), 100)
        if not any(ctx.graph.publishers(part_name(name, p) + EVENT_SUFFIX) for p in PARTS):
            sys.stderr.write(f"{name}: no introspection events yet (its server turns them on "
                             "with configure_introspection); feedback and status follow\n")
            sys.stderr.flush()
        ended = echo.wait(args.timeout)
    finally:
        for sub in raw:
            sub.undeclare()
        node.close()
    if not ended and args.timeout and not echo.count:
        raise CliError(f"nothing from action {name} within {args.timeout:g} s")
    return 0
