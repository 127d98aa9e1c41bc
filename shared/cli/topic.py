"""`zenros topic list|info|type|echo|pub|hz|bw|delay`."""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import threading
import time
from collections import deque
from itertools import pairwise
from typing import Any

import zenoh
from zenoh import ext as zext

from ..codec import from_builtins
from ..names import resolve
from ..qos import QoSProfile
from .common import (
    CliError,
    ToolNode,
    add_common,
    check_graph_type,
    find_message_type,
    open_context,
    parse_yaml_arg,
    payload_to_data,
    print_data,
    stdout_closed,
)


def register(sub: Any) -> None:
    p = sub.add_parser("topic", help="topics: list, info, type, echo, pub, hz, bw, delay")
    verbs = p.add_subparsers(dest="verb", required=True)
    v = verbs.add_parser("list", help="list topics")
    v.add_argument("-t", "--show-types", action="store_true")
    v.add_argument("--wait", type=float, default=0.0, help=argparse.SUPPRESS)
    v = verbs.add_parser("info", help="publishers and subscribers of a topic")
    v.add_argument("topic")
    v.add_argument("-v", "--verbose", action="store_true")
    v = verbs.add_parser("type", help="the type of a topic")
    v.add_argument("topic")
    v = verbs.add_parser("echo", help="print messages")
    v.add_argument("topic")
    v.add_argument("--once", action="store_true", help="print one message and exit")
    v.add_argument("-n", "--count", type=int, default=0, help="exit after N messages")
    v.add_argument("--json", action="store_true", help="one JSON object per line")
    v.add_argument("--timeout", type=float, default=0.0, help="give up after N seconds")
    v = verbs.add_parser("pub", help="publish a message")
    v.add_argument("topic")
    v.add_argument("type")
    v.add_argument("values", nargs="?", default="{}")
    g = v.add_mutually_exclusive_group()
    g.add_argument("-r", "--rate", type=float, default=1.0, help="publish at HZ (default 1)")
    g.add_argument("-1", "--once", action="store_true", help="publish once and exit")
    v.add_argument("-t", "--times", type=int, default=0, help="exit after N messages")
    v.add_argument("-w", "--wait-matching-subscriptions", type=int, default=1, dest="wait_subs",
                   help="with --once/-t: wait for N subscribers first (default 1)")
    v = verbs.add_parser("hz", help="message rate")
    v.add_argument("topic")
    v.add_argument("-w", "--window", type=int, default=10000)
    v.add_argument("--count", type=int, default=0, help="exit after N reports")
    v = verbs.add_parser("delay", help="delay from each message's header stamp to its "
                                       "arrival (ros2 topic delay)")
    v.add_argument("topic")
    v.add_argument("-w", "--window", type=int, default=10000)
    v.add_argument("--count", type=int, default=0, help="exit after N reports")
    v.add_argument("--use-sim-time", action="store_true",
                   help="measure against /clock (a simulation's time), not the wall clock")
    v = verbs.add_parser("bw", help="bandwidth")
    v.add_argument("topic")
    v.add_argument("-w", "--window", type=int, default=100)
    v.add_argument("--count", type=int, default=0, help="exit after N reports")
    for verb in verbs.choices.values():
        add_common(verb)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    waiting = {"echo": "messages on", "hz": "messages on", "bw": "messages on",
               "delay": "messages on",
               "pub": "subscribers of"}.get(args.verb, "")
    ctx = open_context(args, settle=args.verb in ("list", "info", "type"),
                       waiting_for=f"{waiting} {getattr(args, 'topic', '')}")
    try:
        return int(_VERBS[args.verb](ctx, args))
    finally:
        ctx.close()


def _topic(args: argparse.Namespace) -> str:
    return resolve(args.topic)


def _list(ctx: Any, args: argparse.Namespace) -> int:
    for name, types in ctx.graph.topics().items():
        print(f"{name} [{', '.join(types)}]" if args.show_types else name)
    return 0


def _info(ctx: Any, args: argparse.Namespace) -> int:
    topic = _topic(args)
    g = ctx.graph
    types = g.topics().get(topic)
    if not types:
        raise CliError(f"unknown topic {topic}; known: {', '.join(g.topics()) or 'none'}")
    print(f"Type: {', '.join(types)}")
    for label, toks in (("Publisher", g.publishers(topic)), ("Subscription", g.subscribers(topic))):
        print(f"{label} count: {len(toks)}")
        if args.verbose:
            for t in toks:
                print(f"  node: {t.node}  type: {t.type}  qos: {t.qos}  session: {t.zid}")
    return 0


def _type(ctx: Any, args: argparse.Namespace) -> int:
    topic = _topic(args)
    types = ctx.graph.topics().get(topic)
    if not types:
        raise CliError(f"unknown topic {topic}")
    print("\n".join(types))
    return 0


def _subscribe(ctx: Any, topic: str, fn: Any, history: bool = False) -> Any:
    """A raw subscriber (any type); with ``history``, one that also gets latched samples."""
    if history:
        return zext.declare_advanced_subscriber(
            ctx.session, ctx.keys.topic(topic), fn,
            history=zext.HistoryConfig(detect_late_publishers=True, max_samples=100),
            recovery=zext.RecoveryConfig(heartbeat=True, periodic_queries=None),
            subscriber_detection=True,
        )
    return ctx.session.declare_subscriber(ctx.keys.topic(topic), fn)


def _echo(ctx: Any, args: argparse.Namespace) -> int:
    topic = _topic(args)
    limit = 1 if args.once else args.count
    done = threading.Event()
    count = 0
    lock = threading.Lock()

    def on_sample(sample: zenoh.Sample) -> None:
        nonlocal count
        with lock:
            if done.is_set():
                return
            data = payload_to_data(sample.payload.to_bytes(), str(sample.encoding))
            try:
                print_data(data, args.json)
            except BrokenPipeError:
                stdout_closed()
                done.set()
                return
            count += 1
            if limit and count >= limit:
                done.set()

    ctx.graph.settle(quiet=0.2, timeout=1.0)
    publishers = ctx.graph.publishers(topic)
    latched = any(QoSProfile.from_tag(t.qos).latched for t in publishers)
    sub = _subscribe(ctx, topic, on_sample, history=latched)
    if not publishers:
        _say(f"no publisher on {topic} yet; waiting for one"
             + (f" (at most {args.timeout:g} s)" if args.timeout else " (Ctrl-C to stop)"))
    try:
        got = done.wait(args.timeout or None)
    except KeyboardInterrupt:
        got = True
    finally:
        sub.undeclare()
    if not got and args.timeout:
        raise CliError(f"{_nothing_came(ctx, topic, count, limit)} within {args.timeout:g} s")
    return 0


def _nothing_came(ctx: Any, topic: str, count: int, limit: int) -> str:
    """Why an echo with --timeout ended: no publisher at all, or too few messages."""
    what = f"only {count} of {limit} messages" if count else "no message"
    pubs = sorted({t.node for t in ctx.graph.publishers(topic)})
    if not pubs:
        return f"{what} on {topic}: it has no publisher"
    return f"{what} on {topic} (published by {', '.join(pubs)})"


def _say(text: str) -> None:
    """A status line for the user, on stderr (stdout carries only the data)."""
    sys.stderr.write(text + "\n")
    sys.stderr.flush()


def _pub(ctx: Any, args: argparse.Namespace) -> int:
    msg_type = find_message_type(args.type)
    msg = from_builtins(parse_yaml_arg(args.values), msg_type)
    topic = _topic(args)
    ctx.graph.settle(quiet=0.2, timeout=1.0)
    check_graph_type("topic", topic, msg_type.__msgtype__, ctx.graph.topics().get(topic))
    node = ToolNode(f"zenros_topic_pub_{_pid()}", context=ctx)
    pub = node.create_publisher(msg_type, args.topic)
    limit = 1 if args.once else args.times
    if not limit:
        _say(f"publishing {msg_type.__msgtype__} on {pub.topic} at {args.rate:g} Hz until Ctrl-C"
             " (-1 publishes once, -t N N times, -r HZ sets the rate)")
    if limit and args.wait_subs and not pub.wait_for_subscribers(args.wait_subs, 5.0):
        print(f"warning: no subscriber on {pub.topic} after 5 s; publishing anyway",
              file=sys.stderr)
    sent = 0
    rate = node.create_rate(args.rate) if not args.once else None
    try:
        while True:
            pub.publish(msg)
            sent += 1
            print(f"publishing #{sent}: {msg}")
            if limit and sent >= limit:
                break
            assert rate is not None
            rate.sleep()
    except KeyboardInterrupt:
        pass
    finally:
        node.close()
    return 0


def _pid() -> int:
    import os

    return os.getpid()


def _report_loop(ctx: Any, args: argparse.Namespace, report: Any) -> int:
    topic = _topic(args)
    stamps: deque[tuple[float, int]] = deque(maxlen=args.window)
    lock = threading.Lock()

    def on_sample(sample: zenoh.Sample) -> None:
        with lock:
            stamps.append((time.monotonic(), len(sample.payload)))

    sub = _subscribe(ctx, topic, on_sample)
    ctx.graph.settle(quiet=0.2, timeout=1.0)
    if not ctx.graph.publishers(topic):
        _say(f"no publisher on {topic} yet; waiting for one (Ctrl-C to stop)")
    reports = 0
    try:
        while not args.count or reports < args.count:
            time.sleep(1.0)
            with lock:
                snap = list(stamps)
            if len(snap) < 2:
                print("no new messages")
                continue
            report(snap)
            reports += 1
    except KeyboardInterrupt:
        pass
    finally:
        sub.undeclare()
    return 0


def _hz(ctx: Any, args: argparse.Namespace) -> int:
    def report(snap: list[tuple[float, int]]) -> None:
        gaps = [b[0] - a[0] for a, b in pairwise(snap)]
        mean = statistics.fmean(gaps)
        std = statistics.pstdev(gaps)
        rate = 1.0 / mean if mean > 0 else math.inf
        print(f"average rate: {rate:.3f}\n\tmin: {min(gaps):.3f}s max: {max(gaps):.3f}s "
              f"std dev: {std:.5f}s window: {len(snap)}", flush=True)

    return _report_loop(ctx, args, report)


def _bw(ctx: Any, args: argparse.Namespace) -> int:
    def report(snap: list[tuple[float, int]]) -> None:
        span = snap[-1][0] - snap[0][0]
        total = sum(n for _, n in snap[1:])
        sizes = [n for _, n in snap]
        bps = total / span if span > 0 else 0.0
        print(f"{_human(bps)}/s from {len(snap)} messages\n\tMessage size mean: "
              f"{_human(statistics.fmean(sizes))} min: {_human(min(sizes))} "
              f"max: {_human(max(sizes))}", flush=True)

    return _report_loop(ctx, args, report)


def _human(n: float) -> str:
    for unit in ("B", "KB", "MB", "GB"):
        if n < 1000:
            return f"{n:.2f} {unit}"
        n /= 1000
    return f"{n:.2f} TB"


def _header_stamp_ns(data: Any) -> int | None:
    """``header.stamp`` of a decoded message, in ns; None if it has none."""
    try:
        stamp = data["header"]["stamp"]
        return int(stamp["sec"]) * 1_000_000_000 + int(stamp["nanosec"])
    except (KeyError, TypeError, ValueError):
        return None


def _delay(ctx: Any, args: argparse.Namespace) -> int:
    """ros2 topic delay: now (the wall clock, or /clock's time) minus each message's
    ``header.stamp``, reported every second over the last ``--window`` messages."""
    topic = _topic(args)
    delays: deque[float] = deque(maxlen=args.window)
    lock = threading.Lock()
    unstamped = threading.Event()
    sim: list[tuple[int, float]] = []  # (/clock ns, monotonic when it came)

    def now_ns() -> int:
        if not args.use_sim_time:
            return time.time_ns()
        with lock:
            if not sim:
                return -1
            clock, at = sim[-1]
        return clock + int((time.monotonic() - at) * 1e9)

    def on_sample(sample: zenoh.Sample) -> None:
        now = now_ns()
        stamp = _header_stamp_ns(payload_to_data(sample.payload.to_bytes(),
                                                 str(sample.encoding)))
        if stamp is None:
            unstamped.set()
            return
        if now >= 0:
            with lock:
                delays.append((now - stamp) / 1e9)

    def on_clock(sample: zenoh.Sample) -> None:
        c = _header_stamp_ns({"header": {"stamp": payload_to_data(
            sample.payload.to_bytes(), str(sample.encoding)).get("clock")}})
        if c is not None:
            with lock:
                sim[-1:] = [(c, time.monotonic())]

    subs = [_subscribe(ctx, topic, on_sample)]
    if args.use_sim_time:
        subs.append(ctx.session.declare_subscriber(ctx.keys.topic("/clock"), on_clock))
    ctx.graph.settle(quiet=0.2, timeout=1.0)
    if not ctx.graph.publishers(topic):
        _say(f"no publisher on {topic} yet; waiting for one (Ctrl-C to stop)")
    reports = 0
    try:
        while not args.count or reports < args.count:
            time.sleep(1.0)  # a report a second, as ros2 topic delay
            if unstamped.is_set():
                raise CliError(f"messages on {topic} have no header.stamp: topic delay "
                               "needs a stamped type (std_msgs/Header header)")
            with lock:
                snap = list(delays)
            if not snap:
                print("no new messages" if not args.use_sim_time or sim
                      else "no /clock yet (is the simulation publishing it?)")
                continue
            print(f"average delay: {statistics.fmean(snap):.3f}\n\tmin: {min(snap):.3f}s "
                  f"max: {max(snap):.3f}s std dev: {statistics.pstdev(snap):.5f}s "
                  f"window: {len(snap)}", flush=True)
            reports += 1
    except KeyboardInterrupt:
        pass
    finally:
        for sub in subs:
            sub.undeclare()
    return 0


_VERBS = {"list": _list, "info": _info, "type": _type, "echo": _echo, "pub": _pub,
          "hz": _hz, "bw": _bw, "delay": _delay}
