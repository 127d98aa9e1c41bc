"""A Zenoh router's cost per connected session at rest: its CPU and memory as sessions with
a robot's worth of liveliness tokens connect, for sizing a site's routers (docs/fleet.md).

Starts one router (``python -m zenros.router``, as ``zenros launch`` does) and, in a second
process, opens client sessions to it in steps (``--steps``, default 0,25,50,100); each session
declares ``--tokens`` liveliness tokens (default 157: what one composed robot of
deploy/launch/fleet.yaml, with the fleet gateway's view of it, declares), keys as long as
zenros's (about 120 bytes), and one liveliness subscriber on its own robot's tokens. At
each step, after the tokens have settled, the router's CPU (/proc/<pid>/stat) over
``--window`` seconds and its resident memory are measured, and also the sessions' process's
CPU (the reference: the same window, every session). Prints one JSON line: per step
``sessions``, ``tokens``, ``router_cores``, ``router_rss_mb``, ``clients_cores``;
``per_session_kb`` (router memory per added session, from the first step to the last) and
``per_session_cores``; and the load average.

Run: ``python bench/router_scale.py [--steps 0,25,50,100] [--tokens 157] [--window 10]``.
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from _harness import emit, free_port
from zenros.router import router_reachable
from zenros.testing import Proc

CLIENTS = """
import json, sys, zenoh
endpoint, prefix, tokens = sys.argv[1], sys.argv[2], int(sys.argv[3])
sessions, held = [], []
for line in sys.stdin:
    want = int(line)
    while len(sessions) < want:
        k = len(sessions)
        c = zenoh.Config()
        c.insert_json5("mode", '"client"')
        c.insert_json5("connect/endpoints", json.dumps([endpoint]))
        c.insert_json5("scouting/multicast/enabled", "false")
        c.insert_json5("transport/link/tx/lease", "1000")
        s = zenoh.open(c)
        base = f"{prefix}/alive/pub/%robot{k}%chassis/%robot{k}%some%topic/sensor_msgs%msg%LaserScan"
        held += [s.liveliness().declare_token(f"{base}/r:1/{s.zid()}/{i}") for i in range(tokens)]
        held.append(s.liveliness().declare_subscriber(f"{prefix}/alive/*/%robot{k}%chassis/**",
                                                      lambda sample: None))
        sessions.append(s)
    print("ready", len(sessions), flush=True)
"""


def cpu_seconds(pid: int) -> float:
    """User and system CPU seconds of the whole process (/proc/<pid>/stat), threads that
    ended included: a router's runtime threads come and go, so summing the live threads'
    schedstat, as bench/fleet.py does, can go backwards here."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", default="0,25,50,100")
    ap.add_argument("--tokens", type=int, default=157)
    ap.add_argument("--window", type=float, default=10.0)
    ap.add_argument("--settle", type=float, default=5.0)
    args = ap.parse_args()
    steps = [int(s) for s in args.steps.split(",")]
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    router = Proc([sys.executable, "-m", "zenros.router", "-l", endpoint])
    clients_p: subprocess.Popen[str] | None = None
    rows: list[dict[str, float]] = []
    try:
        deadline = time.monotonic() + 15
        while not router_reachable(endpoint, 0.2):
            if router.popen.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"no router on {endpoint}: {router.output}")
            time.sleep(0.1)
        clients_p = subprocess.Popen(
            [sys.executable, "-c", CLIENTS, endpoint, "routerscale", str(args.tokens)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, start_new_session=True)
        assert clients_p.stdin is not None and clients_p.stdout is not None
        for n in steps:
            clients_p.stdin.write(f"{n}\n")
            clients_p.stdin.flush()
            line = clients_p.stdout.readline()
            if not line.startswith("ready"):
                raise RuntimeError(f"clients: {line!r}")
            time.sleep(args.settle)
            r0, c0, t0 = (cpu_seconds(router.popen.pid), cpu_seconds(clients_p.pid),
                          time.monotonic())
            time.sleep(args.window)
            dt = time.monotonic() - t0
            rows.append({
                "sessions": n, "tokens": n * args.tokens,
                "router_cores": round((cpu_seconds(router.popen.pid) - r0) / dt, 4),
                "router_rss_mb": round(rss_mb(router.popen.pid), 1),
                "clients_cores": round((cpu_seconds(clients_p.pid) - c0) / dt, 4),
                "load": round(os.getloadavg()[0], 1)})
        first, last = rows[0], rows[-1]
        added = max(1, last["sessions"] - first["sessions"])
        emit("router_scale", {
            "tokens_per_session": args.tokens, "steps": rows,
            "per_session_kb": round((last["router_rss_mb"] - first["router_rss_mb"]) * 1024
                                    / added, 1),
            "per_session_cores": round((last["router_cores"] - first["router_cores"]) / added,
                                       5),
        })
    finally:
        if clients_p is not None and clients_p.poll() is None:
            os.killpg(clients_p.pid, signal.SIGKILL)
            clients_p.wait(10)
        router.stop()


if __name__ == "__main__":
    main()
