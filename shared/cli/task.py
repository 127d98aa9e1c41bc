"""`zenros task list|show|create|start|pause|resume|stop|delete`: the tasks service's tasks."""

from __future__ import annotations

import argparse
from typing import Any

import msgspec

from ..context import Context
from ..msgs.zenros_msgs import tasks as tm
from ..msgs.zenros_msgs.result import ResultCode
from ..names import resolve
from ..rpc import Client
from .common import (
    CliError,
    add_common,
    open_context,
    parse_yaml_arg,
    print_data,
)

_VERBS = {
    "list": "list tasks: id, state, progress, name",
    "show": "one task, whole (YAML, or --json)",
    "create": "create a task from YAML/JSON: '{name: t, sub_tasks: [{type: sleep_action, wait_time: 1}]}'",
    "start": "start a WAITTING (or finished) task",
    "pause": "pause the running task (the robot stops; resume continues the same action)",
    "resume": "resume a PAUSED task",
    "stop": "stop a task (no id: the running one)",
    "delete": "delete a task that is not running",
}


def register(sub: Any) -> None:
    p = sub.add_parser("task", help="robot tasks (the tasks service): list, show, start, ...")
    verbs = p.add_subparsers(dest="verb", required=True)
    for verb, text in _VERBS.items():
        v = verbs.add_parser(verb, help=text)
        if verb == "create":
            v.add_argument("body", help="the task, YAML flow style or JSON")
            v.add_argument("--start", action="store_true",
                           help="start it once created (else it waits for `task start ID`)")
        elif verb == "stop":
            v.add_argument("id", nargs="?", default="")
        elif verb != "list":
            v.add_argument("id")
        v.add_argument("--ns", default="/", help="the robot's namespace (default /)")
        v.add_argument("--timeout", type=float, default=15.0)
        v.add_argument("--json", action="store_true", help="print JSON")
        add_common(v)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args, settle=False)
    try:
        call = {"list": "get", "show": "get"}.get(args.verb, args.verb)
        body = parse_yaml_arg(args.body) if call == "create" else None
        data = _call(ctx, args, args.verb, call, getattr(args, "id", ""), body)
        if call == "create" and args.start:
            data = _call(ctx, args, "start", "start", data["id"], None) or data
        if args.verb == "list" and not args.json:
            _table(data)
        else:
            print_data(data, args.json, separator=False)
        return 0
    finally:
        ctx.close()


def _call(ctx: Context, args: argparse.Namespace, verb: str, call: str, ident: str,
          body: Any) -> Any:
    """One ``tasks/<call>`` service call: its answer's document(s) ({} if none)."""
    name = resolve(f"tasks/{call}", namespace=args.ns, kind="service")
    client = Client(ctx, tm.TASK_SERVICES[call], name)
    if not client.wait_for_service(min(args.timeout, 5.0)):
        raise CliError(f"service {name} is not available: is the tasks service running?"
                       " (zenros launch deploy/launch/sim.yaml starts it)")
    try:
        request = tm.task_request(call, ident, body)
    except msgspec.ValidationError as exc:
        raise CliError(f"{verb}: invalid task: {exc}") from None
    reply = client.call(request, timeout=args.timeout, grace=args.timeout)
    if reply.code != ResultCode.OK:
        raise CliError(f"{verb}: {reply.message} ({ResultCode(reply.code).name})")
    data = tm.response_data(reply, single=verb == "show")
    return {} if data is None else data


def _table(tasks: list[dict[str, Any]]) -> None:
    if not tasks:
        print("no tasks")
        return
    for t in tasks:
        cur = t.get("current_task") or {}
        now = f"  at {cur.get('type', '')}" if cur and t["state"] in ("WORKING", "PAUSED") else ""
        loops = f"  loops {t['loop_count']}" if t.get("loop_flag") else ""
        print(f"{t['id']}  {t['state']:<9} {t['progress'] * 100:5.1f}%  {t['name']}{now}{loops}")
