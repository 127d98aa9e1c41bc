"""Respawn benchmark: a respawnable node killed with -9 under ``zenros launch``, back in the
graph; against a bare zenoh-python process started fresh on the same router.

Prints one JSON line with:

- ``respawn_s_p50`` / ``respawn_s_max``: from the ``kill -9`` of the launched talker
  (``respawn: true``) until a node of its name with another pid is in the graph: the
  supervisor's reaction, the new interpreter's imports, its Zenoh session and its node's
  liveliness token.
- ``bare_start_s_p50`` / ``bare_start_s_max``: from the start of a ``python -c`` that imports
  zenoh, opens a session to the same router and declares a liveliness token, until that token
  is seen: what any Python process on Zenoh pays for the same steps.
- ``respawn_ratio``: the medians' ratio, zenros / bare.

The two are measured in turn in each of ``--repeats`` rounds (about 11 s each: the talker
runs the supervisor's crash window before each kill), so load that comes and goes hits both.

Run: ``python bench/respawn.py [--repeats N]``.
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from _harness import emit, free_port, unique_prefix
from zenros.context import Context
from zenros.session import SessionOptions
from zenros.testing import Proc

LAUNCH = """
nodes:
  - module: zenros.examples.talker
    name: chatty
    respawn: true
    params: [{rate: 20.0}]
"""

# The reference runs as `python -c`, importing zenoh alone: a child that imported this script
# (or _harness) would pay zenros's imports too (0.31 s where this takes 0.05 s).
BARE = """
import json, sys, zenoh
c = zenoh.Config()
c.insert_json5("mode", '"peer"')
c.insert_json5("connect/endpoints", json.dumps([sys.argv[1]]))
c.insert_json5("scouting/multicast/enabled", "false")
s = zenoh.open(c)
t = s.liveliness().declare_token(sys.argv[2])
sys.stdin.read()
"""


CRASH_WINDOW = 10.0  # the supervisor's: a run this short that fails is a quick failure


def _respawn_once(ctx: Context, up_since: float, timeout: float) -> float:
    """One kill and return. The talker has run a crash window first, so each kill is a
    single crash (respawned at once), not a crash loop (backed off, then given up)."""
    g = ctx.graph
    if not g.wait_for(lambda: any(n.name == "/chatty" for n in g.nodes()), timeout):
        raise RuntimeError("the talker is not in the graph")
    time.sleep(max(0.0, up_since + CRASH_WINDOW + 0.5 - time.monotonic()))
    old = next(n for n in g.nodes() if n.name == "/chatty")
    os.kill(old.pid, signal.SIGKILL)
    start = time.monotonic()
    if not g.wait_for(lambda: any(n.name == "/chatty" and n.pid != old.pid for n in g.nodes()),
                      timeout):
        raise RuntimeError("the talker did not come back")
    return time.monotonic() - start


def _bare_once(ctx: Context, endpoint: str, timeout: float) -> float:
    key = f"bench/respawn/{unique_prefix()}"
    seen = threading.Event()
    sub = ctx.session.liveliness().declare_subscriber(key, lambda s: seen.set())
    start = time.monotonic()
    p = subprocess.Popen([sys.executable, "-c", BARE, endpoint, key], stdin=subprocess.PIPE)
    try:
        if not seen.wait(timeout):
            raise RuntimeError("the bare session's token was not seen")
        return time.monotonic() - start
    finally:
        assert p.stdin is not None
        p.stdin.close()
        p.wait(10)
        sub.undeclare()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeats", type=int, default=6)
    args = ap.parse_args()
    endpoint, prefix = f"tcp/127.0.0.1:{free_port()}", unique_prefix()
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "launch.yaml").write_text(LAUNCH)
        proc = Proc([sys.executable, "-m", "zenros.cli", "launch", str(Path(tmp) / "launch.yaml"),
                     "--data-dir", str(Path(tmp) / "home")],
                    env={"ZENROS_CONNECT": endpoint, "ZENROS_PREFIX": prefix})
        ctx: Context | None = None
        try:
            if not proc.wait_line("started a Zenoh router", 60):
                raise RuntimeError(proc.output)
            ctx = Context(SessionOptions(connect=[endpoint]), prefix=prefix)
            respawn: list[float] = []
            bare: list[float] = []
            up_since = time.monotonic()
            for _ in range(args.repeats):
                respawn.append(_respawn_once(ctx, up_since, 60))
                up_since = time.monotonic()
                bare.append(_bare_once(ctx, endpoint, 60))
        finally:
            if ctx is not None:
                ctx.close()
            proc.stop(timeout=20)
    emit("respawn", {
        "repeats": args.repeats,
        "respawn_s_p50": round(statistics.median(respawn), 3),
        "respawn_s_max": round(max(respawn), 3),
        "bare_start_s_p50": round(statistics.median(bare), 3),
        "bare_start_s_max": round(max(bare), 3),
        "respawn_ratio": round(statistics.median(respawn) / statistics.median(bare), 2),
        "load_after": round(os.getloadavg()[0], 1),
    })


if __name__ == "__main__":
    main()
