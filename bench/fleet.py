"""Fleet benchmark: N simulated robots on this box (`deploy/launch/fleet.yaml`), at rest and
driving, against one robot alone and a bare zenoh-python session in the same topology.

Prints one JSON line with:

- ``robots``: how many robots the launch ran (``--robots``, default 10).
- ``graph_converge_s``: from the launch's start until every robot's chassis, nav, tf and
  tasks are in the graph.
- ``idle_cores_per_robot``: CPU time (every thread's, from /proc schedstat) of the robots' processes over
  ``--window`` seconds at rest, per robot and wall second (target <= 0.06).
- ``idle_process_ratio``: a zenros node process at rest (an ``add_two_ints_server``, which
  only waits for requests) / a bare zenoh-python session process at rest, both connected to
  the launch's router beside the fleet, CPU over the same window (target <= 2.0).
- ``goal_time_ratio``: every robot driving ``--ahead`` metres at once (from the first goal
  sent to the last result) / robot1 driving the same distance alone (target <= 1.3).
- ``reached``: how many of the robots' simultaneous goals succeeded (``10 of 10``).
- ``compose``: whether each robot was one process (fleet.yaml's ``compose``).
- ``gateway_idle_cores``: the fleet's one gateway (fleet.yaml's, every robot's API, 10 Hz
  status each) at rest over the same window; null with ``--no-gateway``.

Run: ``python bench/fleet.py [--robots N] [--window S] [--no-compose] [--no-gateway]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

from _harness import cpu_seconds, emit, free_port, unique_prefix
from zenros.action import ActionClient
from zenros.context import Context
from zenros.msgs.geometry_msgs import PoseStamped
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal
from zenros.msgs.std_msgs import Header
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import Proc

ROOT = Path(__file__).resolve().parents[1]
SPACING = 2.5  # fleet.yaml: robot k starts at ((k - 1) * 2.5, 0, 0)
SERVICES = ("chassis", "nav", "tf", "tasks")
# The reference: a zenoh-python session and nothing else, configured as zenros configures
# every process of the launch (`build_config`: peer, connected to the launch's router, its own
# loopback listener, 1 s lease, the same Zenoh runtime settings). It waits for SIGINT with the
# signals blocked (not on stdin, which is at EOF when the bench runs without a terminal: the
# session then closed at once and measured 0.0).
BARE = """
import signal, sys, zenoh
from zenros.session import SessionOptions, apply_runtime_defaults, build_config
signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})  # Zenoh's threads too
apply_runtime_defaults()
s = zenoh.open(build_config(SessionOptions(connect=[sys.argv[1]])))
print("open", flush=True)
signal.sigwait({signal.SIGINT, signal.SIGTERM})
s.close()
"""


def cpu_rates(pids: dict[str, int], window: float) -> dict[str, float]:
    """Cores each process used over ``window`` wall seconds."""
    before = {k: cpu_seconds(p) for k, p in pids.items()}
    t0 = time.monotonic()
    time.sleep(window)
    dt = time.monotonic() - t0
    return {k: (cpu_seconds(p) - before[k]) / dt for k, p in pids.items()}


def drive(node: Node, robots: list[int], ahead: float, timeout: float) -> tuple[float, int]:
    """Send each robot a goal ``ahead`` metres in front of its start; (seconds, succeeded)."""
    clients = {k: ActionClient(node, NavigateToPose, f"/robot{k}/navigate_to_pose")
               for k in robots}
    for c in clients.values():
        if not c.wait_for_server(60):
            raise RuntimeError(f"no {c.name} server")
    t0 = time.monotonic()
    handles = []
    for k, c in clients.items():
        target = PoseStamped(header=Header(frame_id="map"))
        target.pose.position.x = (k - 1) * SPACING + ahead
        target.pose.orientation.w = 1.0
        handles.append(c.send_goal_async(NavigateToPoseGoal(pose=target)))
    ok = sum(h.result(timeout).succeeded for h in handles)
    elapsed = time.monotonic() - t0
    back = {k: ActionClient(node, NavigateToPose, f"/robot{k}/navigate_to_pose") for k in robots}
    for k, c in back.items():  # home again, for the next run
        home = PoseStamped(header=Header(frame_id="map"))
        home.pose.position.x = (k - 1) * SPACING
        home.pose.orientation.w = 1.0
        handles.append(c.send_goal_async(NavigateToPoseGoal(pose=home)))
    for h in handles[len(robots):]:
        h.result(timeout)
    for c in [*clients.values(), *back.values()]:
        c.close()
    return elapsed, ok


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robots", type=int, default=10)
    ap.add_argument("--window", type=float, default=20.0, help="idle measurement (s)")
    ap.add_argument("--ahead", type=float, default=1.2, help="goal distance (m)")
    ap.add_argument("--no-compose", dest="compose", action="store_false")
    ap.add_argument("--no-gateway", dest="gateway", action="store_false")
    args = ap.parse_args()
    home = Path(tempfile.mkdtemp(prefix="zenros-fleet-"))
    prefix, endpoint = unique_prefix(), f"tcp/127.0.0.1:{free_port()}"
    env = {"ZENROS_HOME": str(home), "ZENROS_PREFIX": prefix, "ZENROS_CONNECT": endpoint}
    t0 = time.monotonic()
    launch = Proc([sys.executable, "-m", "zenros.cli", "launch",
                   str(ROOT / "deploy" / "launch" / "fleet.yaml"), f"robots:={args.robots}",
                   f"compose:={'true' if args.compose else 'false'}", f"data:={home}",
                   f"gateway:={'true' if args.gateway else 'false'}",
                   *(f"{name}:={free_port()}" for name in (
                       "rest_port", "ws_port", "rosbridge_port", "modbus_port"))], env=env)
    ctx: Context | None = None
    extra: list[Proc] = []
    try:
        if not launch.wait_line("started a Zenoh router", 60):
            raise RuntimeError(launch.output)
        # a client of the launch's router: it sees every token the router has, not only
        # those of the peers it found by gossip (docs/zenoh-config.md, "Known limit")
        ctx = Context(SessionOptions(mode="client", connect=[endpoint]), prefix=prefix)
        g = ctx.graph
        want = {f"/robot{k}/{s}" for k in range(1, args.robots + 1) for s in SERVICES}
        if not g.wait_for(lambda: want <= set(g.node_names()), 600):
            raise RuntimeError(f"not in the graph: {sorted(want - set(g.node_names()))}")
        converge = time.monotonic() - t0
        robot_pids = {n.name: n.pid for n in g.nodes() if n.name in want}
        gateway: dict[str, int] = {}
        if args.gateway:
            views = {"/gateway", *(f"/robot{k}/gateway" for k in range(1, args.robots + 1))}
            if not g.wait_for(lambda: views <= set(g.node_names()), 120):
                raise RuntimeError("the gateway does not serve every robot: no "
                                   f"{sorted(views - set(g.node_names()))}")
            gateway = {"gateway": next(n.pid for n in g.nodes() if n.name == "/gateway")}
        bare = Proc([sys.executable, "-c", BARE, endpoint])
        idle = Proc([sys.executable, "-m", "zenros.examples.add_two_ints_server", "-e", endpoint,
                     "--name", "idle_probe"], env=env)
        extra = [bare, idle]
        if not bare.wait_line("open", 60) or not g.wait_for_node("/idle_probe", 60):
            raise RuntimeError(bare.output + idle.output)
        time.sleep(5)  # both settle: first declarations and liveliness exchanges done
        pids = {f"pid{p}": p for p in set(robot_pids.values())}
        rates = cpu_rates({**pids, "bare": bare.popen.pid, "idle": idle.popen.pid, **gateway},
                          args.window)
        for p in extra:  # a reference that ended during the window measured nothing
            if p.popen.poll() is not None:
                raise RuntimeError(f"{p.argv[:3]} ended during the window:\n{p.output}")
        robots_cores = sum(v for k, v in rates.items() if k.startswith("pid"))
        node = Node("fleet_bench", context=ctx)
        alone, _ = drive(node, [1], args.ahead, 120)
        together, reached = drive(node, list(range(1, args.robots + 1)), args.ahead, 180)
        node.close()
        emit("fleet", {
            "robots": args.robots, "compose": args.compose,
            "graph_converge_s": round(converge, 1),
            "idle_cores_per_robot": round(robots_cores / args.robots, 4),
            "idle_process_cores": round(rates["idle"], 4),
            "bare_session_cores": round(rates["bare"], 4),
            "idle_process_ratio": round(rates["idle"] / max(rates["bare"], 1e-4), 2),
            "goal_alone_s": round(alone, 2), "goal_together_s": round(together, 2),
            "goal_time_ratio": round(together / alone, 2),
            "load_after": round(os.getloadavg()[0], 1),
        }, reached=f"{reached} of {args.robots}",
            gateway_idle_cores=round(rates["gateway"], 4) if gateway else None)
    finally:
        for p in extra:
            p.stop()
        if ctx is not None:
            ctx.close()
        launch.stop(timeout=60)


if __name__ == "__main__":
    main()
