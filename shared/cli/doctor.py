"""`zenros doctor`: what is wrong with the running system, as `ros2 doctor` reports it.

Each check prints one line, ``ok`` or what it found; the exit code is 1 when a check found a
problem (0 otherwise), so a script can gate on it (docs/cli.md):

- **links**: the routers and peers this session reached;
- **nodes**: two nodes with one name (different processes);
- **topic types**: a topic published or subscribed with more than one type;
- **QoS**: publisher and subscription pairs a ROS 2 (DDS) system would not connect
  (`zenros.qos_events.incompatible_policy`): zenros delivers them, but a bridged ROS 2 node
  would not;
- **clocks**: the sessions heard for ``--hear`` seconds, each sample's source timestamp
  (its session's clock) against this host's on arrival: a host whose clock is more than
  ``--max-skew`` ahead, or further behind than that plus the transport's delay, is named
  (stamps, TF lookups and deadlines between hosts go wrong with it);
- **zenoh**: the Zenoh version of this process.
"""

from __future__ import annotations

import argparse
import threading
import time
from collections import defaultdict
from importlib.metadata import version
from typing import Any

import zenoh

from ..qos import QoSProfile
from ..qos_events import incompatible_policy
from .common import add_common, open_context

__all__ = ["Finding", "check_graph", "clock_offsets"]

Finding = tuple[str, bool, list[str]]
"""(check, ok, lines): the check's name, whether it passed, what it says."""


def register(sub: Any) -> None:
    p = sub.add_parser("doctor", help="check the running system: links, node names, topic "
                                      "types, QoS, clocks",
                       description="Report what is wrong with the running system "
                                   "(ros2 doctor); exit code 1 when a check found a problem.")
    p.add_argument("--hear", type=float, default=2.0,
                   help="seconds to hear samples for the clock check (default 2)")
    p.add_argument("--max-skew", type=float, default=0.1,
                   help="seconds a host's clock may differ from this one's (default 0.1)")
    add_common(p)
    p.set_defaults(func=run)


def check_graph(graph: Any) -> list[Finding]:
    """The checks the graph alone answers: node names, topic types, QoS pairs."""
    out: list[Finding] = []
    dups = graph.duplicate_nodes()
    names = [f"{name}: {len(infos)} nodes share it ("
             + ", ".join(f"pid {i.pid} on {i.host}" for i in infos) + ")"
             for name, infos in sorted(dups.items())]
    out.append(("nodes", not dups,
                names or [f"{len(graph.node_names())} nodes, no two share a name"]))
    conflicts = graph.type_conflicts()
    types = [f"{topic}: {', '.join(t)}" for topic, t in sorted(conflicts.items())]
    out.append(("topic types", not conflicts,
                types or [f"{len(graph.topics())} topics, one type each"]))
    pairs: list[str] = []
    for topic in sorted(graph.topics()):
        for pub in graph.publishers(topic):
            for sub in graph.subscribers(topic):
                policy = incompatible_policy(QoSProfile.from_tag(pub.qos),
                                             QoSProfile.from_tag(sub.qos))
                if policy is not None:
                    pairs.append(f"{topic}: {pub.node} offers {pub.qos}, {sub.node} requests "
                                 f"{sub.qos} ({policy.name})")
    fine = "every publisher offers what its subscriptions request"
    out.append(("QoS", not pairs, pairs or [fine]))
    return out


def clock_offsets(session: zenoh.Session, key: str, seconds: float) -> dict[str, float]:
    """Per sending session (zid): the smallest (arrival on this host's clock - the sample's
    source timestamp) over ``seconds`` of samples on ``key``: the transport's delay minus
    how far that session's clock is ahead of this one."""
    best: dict[str, float] = {}
    lock = threading.Lock()

    def on_sample(sample: zenoh.Sample) -> None:
        now = time.time_ns()
        ts = sample.timestamp
        if ts is None:
            return
        d = (now - int(ts.get_time_as_ntp64().as_nanos())) / 1e9
        zid = str(ts.get_id())
        with lock:
            if d < best.get(zid, float("inf")):
                best[zid] = d

    sub = session.declare_subscriber(key, on_sample)
    try:
        time.sleep(seconds)  # the listening window the user asked for
    finally:
        sub.undeclare()  # type: ignore[no-untyped-call]
    with lock:
        return dict(best)


def _clocks(ctx: Any, seconds: float, max_skew: float) -> Finding:
    offsets = clock_offsets(ctx.session, ctx.keys.topic("/**"), seconds)
    hosts: dict[str, str] = {}
    for n in ctx.graph.nodes():
        hosts.setdefault(n.zid, n.host)
    if not offsets:
        return ("clocks", True, [f"no sample heard in {seconds:g} s: nothing to compare"])
    bad: dict[str, list[str]] = defaultdict(list)
    for zid, d in offsets.items():
        if d < -max_skew or d > max_skew + 0.5:  # ahead, or behind past the transport's delay
            what = (f"{-d:.3f} s ahead of" if d < 0 else f"at least {d - 0.5:.3f} s behind")
            bad[hosts.get(zid, f"session {zid}")].append(what)
    if bad:
        return ("clocks", False, [f"{host}: its clock is {', '.join(sorted(set(w)))} this "
                                  "host's (sync the hosts' clocks: chrony, NTP)"
                                  for host, w in sorted(bad.items())])
    return ("clocks", True, [(f"{len(offsets)} sessions heard, on "
                             f"{len({hosts.get(z, z) for z in offsets})} host(s): clocks within "
                             f"{max_skew:g} s of this host's")])


def run(args: argparse.Namespace) -> int:
    ctx = open_context(args)
    try:
        info = ctx.session.info
        routers = [str(z) for z in info.routers_zid()]
        peers = [str(z) for z in info.peers_zid()]
        linked = (f"{len(routers)} router(s), {len(peers)} peer(s) linked to this session"
                  if routers or peers else "no router or peer reached (is `zenros router` or "
                  "a launch running? -e ENDPOINT)")
        findings: list[Finding] = [("links", bool(routers or peers), [linked])]
        findings += check_graph(ctx.graph)
        findings.append(_clocks(ctx, args.hear, args.max_skew))
        findings.append(("zenoh", True, [(f"eclipse-zenoh {version('eclipse-zenoh')} (this "
                                         "process)")]))
    finally:
        ctx.close()
    width = max(len(name) for name, _, _ in findings)
    problems = 0
    for name, ok, lines in findings:
        problems += not ok
        print(f"{name:<{width}}  {'ok' if ok else 'PROBLEM'}: {lines[0]}")
        for line in lines[1:]:
            print(f"{'':<{width}}    {line}")
    print(f"{problems} problem(s)" if problems else "no problems found")
    return 1 if problems else 0
