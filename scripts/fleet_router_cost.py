"""What composed robots put on one router at rest: liveliness tokens, router memory and CPU,
bytes through its links per second (docs/fleet.md, "1,000 robots across sites").

    python scripts/fleet_router_cost.py N

Starts a router on a free loopback port and a second ("upstream", as a station's or a
site's router) connected to it, master (fleet.yaml robots:=0 gateway:=false) and N
robots (robot.yaml compose:=true examples:=false heartbeat_rate:=0) as its clients, waits
until every robot's tasks node is in the graph and 15 s more, measures the router for 20 s
(schedstat of its threads, VmRSS, `ss -ti` bytes on its port) and the upstream router (what
reaches a router that no robot connects to: every declaration the robots make), prints one JSON line and stops
everything by process group. Logs go to a temporary folder it names.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import zenoh

ROOT = Path(__file__).resolve().parents[1]
ZENROS = [sys.executable, "-m", "zenros.cli"]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def cpu_seconds(pid: int) -> float:
    total = 0
    for tid in os.listdir(f"/proc/{pid}/task"):
        try:
            total += int(Path(f"/proc/{pid}/task/{tid}/schedstat").read_text().split()[0])
        except (OSError, IndexError, ValueError):
            pass  # the thread ended
    return total / 1e9


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS"):
            return int(line.split()[1]) / 1024
    return 0.0


def link_bytes(port: int) -> int:
    """Bytes acknowledged and received on every TCP connection of the router's port."""
    out = subprocess.run(["ss", "-tinH", f"sport = :{port}"], capture_output=True, text=True,
                         check=False).stdout
    return sum(int(tok.split(":")[1]) for tok in out.split()
               if tok.startswith(("bytes_acked:", "bytes_received:")))


def wait_port(port: int, timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            socket.create_connection(("127.0.0.1", port), 0.5).close()
            return
        except OSError:
            time.sleep(0.2)
    raise SystemExit(f"the router did not listen on port {port} within {timeout:.0f} s")


def start(cmd: list[str], env: dict[str, str], log: Path) -> subprocess.Popen[bytes]:
    with log.open("wb") as out:
        return subprocess.Popen(cmd, env=env, stdout=out, stderr=subprocess.STDOUT,
                                start_new_session=True)


def stop(procs: list[subprocess.Popen[bytes]], sig: signal.Signals) -> None:
    for p in procs:
        try:
            os.killpg(p.pid, sig)
        except ProcessLookupError:
            pass
    for p in procs:
        try:
            p.wait(30)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(5)


def main() -> None:
    robots = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    work = Path(tempfile.mkdtemp(prefix="zenros-router-cost-"))
    port = free_port()
    endpoint = f"tcp/127.0.0.1:{port}"
    prefix = f"rc{os.getpid()}"
    router = start([sys.executable, "-m", "zenros.router", "-l", endpoint], dict(os.environ),
                   work / "router.log")
    up_port = free_port()
    upstream = start([sys.executable, "-m", "zenros.router", "-l", f"tcp/127.0.0.1:{up_port}",
                      "--cfg", f'connect/endpoints:["{endpoint}"]'], dict(os.environ),
                     work / "upstream.log")
    procs: list[subprocess.Popen[bytes]] = []
    try:
        wait_port(port, 30)
        wait_port(up_port, 30)
        time.sleep(1)
        rss_empty, up_rss_empty = rss_mb(router.pid), rss_mb(upstream.pid)
        env = dict(os.environ, ZENROS_CONNECT=endpoint, ZENROS_PREFIX=prefix,
                   ZENROS_HOME=str(work / "home"), ZENROS_MODE="client")
        procs.append(start([*ZENROS, "launch", str(ROOT / "deploy/launch/fleet.yaml"),
                            "robots:=0", "gateway:=false", "--no-router"], env,
                           work / "master.log"))
        for k in range(1, robots + 1):
            procs.append(start([*ZENROS, "launch", str(ROOT / "deploy/launch/robot.yaml"),
                                f"robot:=robot{k}", "compose:=true", "examples:=false",
                                "heartbeat_rate:=0", f"start_pose:=[{2.5 * (k - 1)}, 0, 0]",
                                "--no-router"], env, work / f"robot{k}.log"))
        conf = zenoh.Config()
        conf.insert_json5("mode", '"client"')
        conf.insert_json5("connect/endpoints", json.dumps([endpoint]))
        conf.insert_json5("scouting/multicast/enabled", "false")
        with zenoh.open(conf) as session:
            def tokens() -> list[str]:
                return [str(r.ok.key_expr) for r in session.liveliness().get("**", timeout=3.0)
                        if r.ok is not None]

            deadline = time.monotonic() + 180
            while not all(any(f"%robot{k}%tasks/" in t and "/node/" in t for t in tokens())
                          for k in range(1, robots + 1)):
                if time.monotonic() > deadline:
                    raise SystemExit(f"the robots did not all come up in 180 s (logs in {work})")
                time.sleep(1)
            time.sleep(15)  # at rest
            found = tokens()
            cpu0, bytes0, t0 = cpu_seconds(router.pid), link_bytes(port), time.monotonic()
            up0 = cpu_seconds(upstream.pid)
            time.sleep(20)
            cpu1, bytes1, t1 = cpu_seconds(router.pid), link_bytes(port), time.monotonic()
            up1 = cpu_seconds(upstream.pid)
        print(json.dumps({
            "robots": robots,
            "tokens_total": len(found),
            "tokens_per_robot": [sum(f"%robot{k}%" in t for t in found)
                                 for k in range(1, robots + 1)],
            "router_rss_mb_empty": round(rss_empty, 1),
            "router_rss_mb": round(rss_mb(router.pid), 1),
            "router_cores": round((cpu1 - cpu0) / (t1 - t0), 4),
            "router_link_bytes_per_s": round((bytes1 - bytes0) / (t1 - t0)),
            "upstream_rss_mb_empty": round(up_rss_empty, 1),
            "upstream_rss_mb": round(rss_mb(upstream.pid), 1),
            "upstream_cores": round((up1 - up0) / (t1 - t0), 4),
            "load": round(os.getloadavg()[0], 1),
            "logs": str(work),
        }))
    finally:
        stop(procs, signal.SIGINT)
        stop([upstream, router], signal.SIGTERM)


if __name__ == "__main__":
    main()
