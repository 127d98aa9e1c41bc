"""Run inside a private network namespace (tests/system/test_peer_link_heal.py): a zenros
router, and peers B and C (zenros session defaults plus ``--cfg`` entries from argv) that find
each other by gossip. C publishes to B at 50 Hz; the B-C link is cut with iptables (the
links to the router stay up) until B's lease on it runs out, then restored. Prints one JSON
line: whether C's samples reached B again, and after how long."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time

import zenoh
from zenros.router import build_router_config
from zenros.session import SessionOptions, build_config
from zenros.testing import wait_for

ROUTER, B, C = 7101, 7102, 7103
CUT = ["INPUT", "-p", "tcp", "-m", "multiport", "--ports", f"{B},{C}", "-j", "DROP"]


def peer(port: int, cfg: list[tuple[str, str]]) -> zenoh.Session:
    opts = SessionOptions(listen=[f"tcp/127.0.0.1:{port}"],
                          connect=[f"tcp/127.0.0.1:{ROUTER}"], cfg=cfg)
    conf = build_config(opts)
    conf.insert_json5("transport/shared_memory/enabled", "false")
    return zenoh.open(conf)


def main() -> None:
    cfg = [tuple(a.split(":", 1)) for a in sys.argv[1:]]
    router = zenoh.open(build_router_config([f"tcp/127.0.0.1:{ROUTER}"]))
    b = peer(B, cfg)  # type: ignore[arg-type]
    c = peer(C, cfg)  # type: ignore[arg-type]
    got: list[float] = []
    sub = b.declare_subscriber("heal/c", lambda s: got.append(time.monotonic()))
    pub = c.declare_publisher("heal/c")
    stop = threading.Event()

    def publish() -> None:
        while not stop.wait(0.02):
            pub.put(b"x")

    threading.Thread(target=publish, daemon=True).start()
    out: dict[str, object] = {"linked": wait_for(lambda: len(got) >= 10, 10)}
    c_zid = str(c.info.zid())
    try:
        if out["linked"]:
            subprocess.run(["iptables", "-A", *CUT], check=True)
            try:  # the fault lasts until B's lease on the link ran out: B dropped C
                out["dropped"] = wait_for(
                    lambda: c_zid not in {str(z) for z in b.info.peers_zid()}, 10)
            finally:
                subprocess.run(["iptables", "-D", *CUT], check=True)
            restored = time.monotonic()
            # Flowing again: a second's worth (a few samples may straggle in before a link
            # that is not made again closes for good).
            out["healed"] = wait_for(lambda: sum(t > restored for t in got) >= 50, 10)
            first = min((t for t in got if t > restored), default=None)
            out["first_after_restore_s"] = None if first is None else round(first - restored, 3)
    finally:
        stop.set()
        sub.undeclare()
        for s in (c, b, router):
            s.close()
    print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
