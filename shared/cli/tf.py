"""`zenros tf echo|frames|static`: print a transform, show the frame tree, publish a static link."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import threading
import time
from pathlib import Path
from typing import Any

from ..clock import Rate
from ..codec import to_builtins
from ..context import Context
from ..errors import TransformException
from ..msgs.builtin_interfaces import Time
from ..msgs.geometry_msgs import TransformStamped
from ..msgs.tf_srvs import FrameInfo, Frames, FramesRequest
from ..rpc import Client
from ..tf import (
    LATEST,
    Buffer,
    StaticTransformBroadcaster,
    TransformListener,
    euler_from_quaternion,
    frames_as_dot,
    frames_as_tree,
    frames_from_yaml,
    matrix_from_msg,
    parse_link,
)
from ..tf.client import DEFAULT_SERVER
from ..tf.spec import FORMS
from .common import CliError, ToolNode, add_common, open_context


def register(sub: Any) -> None:
    p = sub.add_parser("tf", help="transforms: echo, frames, static")
    verbs = p.add_subparsers(dest="verb", required=True)
    v = verbs.add_parser("echo", help="print the transform from one frame to another (tf2_echo)")
    v.add_argument("target", help="the frame the result is expressed in (e.g. map)")
    v.add_argument("source", help="the frame whose pose is printed (e.g. base_link)")
    v.add_argument("-r", "--rate", type=float, default=1.0, help="prints per second (default 1)")
    v.add_argument("--once", action="store_true", help="print one transform and exit")
    v.add_argument("-n", "--count", type=int, default=0, help="exit after N transforms")
    v.add_argument("--timeout", type=float, default=0.0,
                   help="give up after N seconds (exit code 1 if nothing was printed)")
    v.add_argument("--json", action="store_true", help="one JSON object per line")
    v = verbs.add_parser("frames", help="the frame tree with authorities and rates (view_frames)")
    v.add_argument("--dot", action="store_true", help="print Graphviz DOT")
    v.add_argument("-o", "--output", help="write DOT to this file")
    v.add_argument("--json", action="store_true", help="the frames as one JSON list")
    v.add_argument("--server", default=DEFAULT_SERVER,
                   help=f"the tf service to ask (default {DEFAULT_SERVER})")
    v.add_argument("--no-server", action="store_true",
                   help="do not ask the tf service: listen to /tf and /tf_static for --wait s")
    v.add_argument("--wait", type=float, default=2.0,
                   help="seconds to listen when there is no tf service (default 2)")
    v = verbs.add_parser(
        "static", help="publish a static transform until Ctrl-C (static_transform_publisher)",
        description=f"Publish one static link on /tf_static. Arguments: {FORMS} (radians).",
    )
    v.add_argument("values", nargs="+", metavar="VALUE",
                   help="x y z yaw pitch roll parent child, or x y z qx qy qz qw parent child")
    v.add_argument("--node-name", default="", help="the publishing node's name")
    for verb in verbs.choices.values():
        add_common(verb)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.verb == "static":
        link = parse_link(args.values)  # before the session: a usage error costs nothing
        ctx = open_context(args, settle=False)
        try:
            return _static(ctx, args, link)
        finally:
            ctx.close()
    waiting = f"the transform {args.target} -> {args.source}" if args.verb == "echo" else ""
    ctx = open_context(args, settle=args.verb == "frames" and not args.no_server,
                       waiting_for=waiting)
    try:
        return _echo(ctx, args) if args.verb == "echo" else _frames(ctx, args)
    finally:
        ctx.close()


# ---------------------------------------------------------------------- echo


def _echo(ctx: Context, args: argparse.Namespace) -> int:
    if not args.rate > 0:
        raise CliError(f"--rate must be > 0, got {args.rate}")
    node = ToolNode(f"zenros_tf_echo_{os.getpid()}", context=ctx)
    try:
        buf = Buffer()
        TransformListener(buf, node)
        limit = 1 if args.once else args.count
        deadline = time.monotonic() + args.timeout if args.timeout else math.inf
        rate = Rate(args.rate)
        printed, last_error = 0, ""
        while True:
            wait = min(rate.period.to_sec(), max(0.0, deadline - time.monotonic()))
            try:
                t = buf.lookup_transform(args.target, args.source, LATEST, wait)
            except TransformException as exc:
                if str(exc) != last_error:
                    last_error = str(exc)
                    print(f"Waiting for transform {args.target} -> {args.source}: {exc}",
                          file=sys.stderr, flush=True)
            else:
                last_error = ""
                _print_transform(t, args.json)
                printed += 1
                if limit and printed >= limit:
                    return 0
                rate.sleep()
            if time.monotonic() >= deadline:
                return 0 if printed else 1
    except KeyboardInterrupt:
        return 0
    finally:
        node.close()


def _print_transform(t: TransformStamped, as_json: bool) -> None:
    """tf2_echo's report: stamp, translation, quaternion, RPY, 4x4 matrix."""
    v, q = t.transform.translation, t.transform.rotation
    rpy = euler_from_quaternion((q.x, q.y, q.z, q.w))
    m = matrix_from_msg(t)
    stamp = t.header.stamp.sec + t.header.stamp.nanosec / 1e9
    if as_json:
        print(json.dumps({
            "stamp": stamp, "target": t.header.frame_id, "source": t.child_frame_id,
            "translation": [v.x, v.y, v.z], "quaternion": [q.x, q.y, q.z, q.w],
            "rpy": list(rpy), "matrix": m.tolist(),
        }), flush=True)  # fmt: skip
        return
    st = t.header.stamp
    lines = [
        f"At time {st.sec}.{st.nanosec:09d}",
        f"- Translation: {_row((v.x, v.y, v.z))}",
        f"- Rotation: in Quaternion (xyzw) {_row((q.x, q.y, q.z, q.w))}",
        f"- Rotation: in RPY (radian) {_row(rpy)}",
        f"- Rotation: in RPY (degree) {_row([math.degrees(a) for a in rpy])}",
        "- Matrix:",
        *("  " + " ".join(f"{_num(c):6.3f}" for c in row) for row in m.tolist()),
    ]
    print("\n".join(lines), flush=True)


def _num(v: float) -> float:
    """``v`` rounded to the 3 printed decimals, without a '-0.000'."""
    return round(v, 3) + 0.0


def _row(values: Any) -> str:
    return "[" + ", ".join(f"{_num(v):.3f}" for v in values) + "]"


# ---------------------------------------------------------------------- frames


def _frames(ctx: Context, args: argparse.Namespace) -> int:
    frames: list[FrameInfo] | None = None
    stamp: Time | None = None
    if not args.no_server:
        client = Client(ctx, Frames, f"{args.server.rstrip('/')}/frames")
        if client.service_is_ready():
            res = client.call(FramesRequest(), timeout=5.0)
            frames, stamp = res.frames, res.stamp
        else:
            print(f"no tf service at {args.server}; listening to /tf and /tf_static for "
                  f"{args.wait:g} s instead", file=sys.stderr)
    if frames is None:
        frames, stamp = _listen(ctx, args.wait)
    if args.output:
        Path(args.output).write_text(frames_as_dot(frames, stamp))
        print(f"wrote {args.output} ({len(frames)} frames)")
    elif args.dot:
        sys.stdout.write(frames_as_dot(frames, stamp))
    elif args.json:
        print(json.dumps([to_builtins(f) for f in frames]))
    else:
        sys.stdout.write(frames_as_tree(frames))
    return 0


def _listen(ctx: Context, seconds: float) -> tuple[list[FrameInfo], Time]:
    """What a listener gathers in ``seconds`` (authorities are tf2's "default_authority")."""
    node = ToolNode(f"zenros_tf_frames_{os.getpid()}", context=ctx)
    try:
        buf = Buffer()
        TransformListener(buf, node)
        threading.Event().wait(seconds)  # a listening window, as view_frames has
        now = node.now()
        return frames_from_yaml(buf.all_frames_as_yaml(now)), now
    finally:
        node.close()


# ---------------------------------------------------------------------- static


def _static(ctx: Context, args: argparse.Namespace, link: TransformStamped) -> int:
    name = args.node_name or f"static_transform_publisher_{os.getpid()}"
    node = ToolNode(name, context=ctx)
    try:
        link.header.stamp = node.now()
        StaticTransformBroadcaster(node).send_transform(link)
        v, q = link.transform.translation, link.transform.rotation
        print(f"publishing static transform {link.header.frame_id} -> {link.child_frame_id}: "
              f"translation ({v.x:g}, {v.y:g}, {v.z:g}), rotation ({q.x:g}, {q.y:g}, {q.z:g}, "
              f"{q.w:g}) as {node.fqn}; Ctrl-C to stop", flush=True)
        while True:  # wakes to run a signal (Ctrl-C) that one of Zenoh's threads took
            time.sleep(0.5)
    except KeyboardInterrupt:
        pass
    finally:
        node.close()
    return 0
