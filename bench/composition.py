"""Composition measured both ways: one robot's services (chassis, nav, tf, tasks) as components
of one process (`deploy/launch/robot.yaml compose:=true`) and as four processes
(``compose:=false``, the reference), each launched alone with its router and master, in
turn.

Prints one JSON line with, for ``composed`` and ``separate`` (the best of ``--repeats``
launches each, the launches alternating so that load that comes and goes hits both):

- ``start_s``: from the launch's start until the four nodes are in the graph.
- ``idle_cores``: CPU time of the robot's processes (every thread's, /proc schedstat) over
  ``--window`` seconds at rest, per wall second; ``idle_cores_by_process`` each one's.
- ``rss_mb``: the robot's processes' resident memory (VmRSS), summed.
- ``tf_delay_ms`` / ``tf_max_delay_ms``: a pub/sub between two of the robot's nodes: chassis
  publishes odom -> base_link on ``/robot1/tf`` at 50 Hz stamped with the wall clock, and the
  tf node's monitor (``/robot1/tf/frames``) reports arrival minus stamp, mean and largest
  over its 10 s window.
- ``processes``: how many processes the robot is.

and ``load`` (the 1-minute load average at the start and at the end: the box is shared).

Run: ``python bench/composition.py [--window S] [--repeats N] [--modes composed,separate]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from _harness import emit, free_port, unique_prefix
from fleet import cpu_rates
from zenros.context import Context
from zenros.msgs.tf_srvs import Frames, FramesRequest
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import Proc

ROOT = Path(__file__).resolve().parents[1]
SERVICES = ("chassis", "nav", "tf", "tasks")
MODES = {"composed": "true", "separate": "false"}
LAUNCH = """
nodes:
  - module: zenros.services.master
include:
  - file: {robot}
    args: {{robot: robot1, compose: "{compose}", examples: "false", data: "{data}"}}
"""


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def measure(compose: str, window: float, settle: float) -> dict[str, Any]:
    """Launch robot1 alone (``compose``), measure it at rest, stop it."""
    home = Path(tempfile.mkdtemp(prefix="zenros-compose-"))
    prefix, endpoint = unique_prefix(), f"tcp/127.0.0.1:{free_port()}"
    env = {"ZENROS_HOME": str(home), "ZENROS_PREFIX": prefix, "ZENROS_CONNECT": endpoint}
    t0 = time.monotonic()
    # master (the parameter server, as a fleet has it) and robot.yaml's robot1
    (home / "launch.yaml").write_text(LAUNCH.format(
        robot=ROOT / "deploy" / "launch" / "robot.yaml", compose=compose, data=home))
    launch = Proc([sys.executable, "-m", "zenros.cli", "launch", str(home / "launch.yaml")],
                  env=env)
    ctx: Context | None = None
    try:
        if not launch.wait_line("started a Zenoh router", 60):
            raise RuntimeError(launch.output)
        ctx = Context(SessionOptions(connect=[endpoint]), prefix=prefix)
        g = ctx.graph
        want = {f"/robot1/{s}" for s in SERVICES}
        if not g.wait_for(lambda: want <= set(g.node_names()), 300):
            raise RuntimeError(f"not in the graph: {sorted(want - set(g.node_names()))}")
        start = time.monotonic() - t0
        by_name = {n.name: n.pid for n in g.nodes() if n.name in want}
        pids = {f"pid{p}": p for p in set(by_name.values())}
        time.sleep(settle)  # every node past its start: maps loaded, first scans applied
        rates = cpu_rates(pids, window)
        names = {p: "+".join(sorted(n.rsplit("/", 1)[1] for n, q in by_name.items() if q == p))
                 for p in set(by_name.values())}
        node = Node("compose_bench", context=ctx)
        frames = node.create_client(Frames, "/robot1/tf/frames")
        if not frames.wait_for_service(30):
            raise RuntimeError("no /robot1/tf/frames")
        link = next(f for f in frames.call(FramesRequest(), timeout=10).frames
                    if f.frame_id == "base_link")
        node.close()
        return {
            "start_s": round(start, 2),
            "idle_cores": round(sum(rates.values()), 4),
            "idle_cores_by_process": {names[p]: round(rates[f"pid{p}"], 4) for p in names},
            "rss_mb": round(sum(rss_mb(p) for p in names), 1),
            "tf_delay_ms": round(link.delay * 1e3, 3),
            "tf_max_delay_ms": round(link.max_delay * 1e3, 2),
            "tf_rate_hz": round(link.rate, 1),
            "processes": len(names),
        }
    finally:
        if ctx is not None:
            ctx.close()
        launch.stop(timeout=60)


def best(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """Each figure's best (lowest) over the runs; the per-process split of the quietest."""
    quiet = min(runs, key=lambda r: r["idle_cores"])
    out = {k: min(r[k] for r in runs) for k in quiet if k != "idle_cores_by_process"}
    out["idle_cores_by_process"] = quiet["idle_cores_by_process"]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--window", type=float, default=20.0, help="idle measurement (s)")
    ap.add_argument("--settle", type=float, default=10.0, help="wait before measuring (s)")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--modes", default=",".join(MODES), help="composed,separate (default)")
    args = ap.parse_args()
    modes = {m: MODES[m] for m in args.modes.split(",")}
    load = [round(os.getloadavg()[0], 1)]
    runs: dict[str, list[dict[str, Any]]] = {m: [] for m in modes}
    for _ in range(args.repeats):
        for mode, compose in modes.items():
            runs[mode].append(measure(compose, args.window, args.settle))
    load.append(round(os.getloadavg()[0], 1))
    emit("composition", {}, **{mode: best(r) for mode, r in runs.items()}, load=load,
         runs=runs)


if __name__ == "__main__":
    main()
