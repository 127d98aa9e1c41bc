"""Reproduce Zenoh 1.10 delivering samples under another key after links drop and come back.

Raw zenoh-python only (no zenros code on the data path): a router, ``--publishers`` peer
processes each publishing on four keys of its own and one shared key (every sample's encoding
schema names the key it was put on), and three subscriber peers checking that each sample's
key and encoding agree. The driver freezes the publishers, then one subscriber, for longer
than the 1 s lease (SIGSTOP/SIGCONT), so their links drop and are made again while data flows.

Prints one JSON line: ``misrouted`` (samples whose encoding names another key than the one
they arrived on), ``received`` and examples. Seen on 2026-12-03 with eclipse-zenoh 1.10.2 on a
2-core box (60 s runs, 6 publishers, about a million samples each): with declared publishers,
misrouted samples in 3 of 6 runs (41, 111, 4,169); with ``--put`` (``session.put``, no key
declared by the sender) in 2 of 5 runs (3,155, 8,595). So it is not the sender's key
declaration. zenros tags every sample with its key (`zenros.keytag`), so its subscribers drop
such samples.

Run: ``python scripts/zenoh_misrouting.py [--seconds 60] [--publishers 6] [--put]``.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import time

PEER = r"""
import json, sys, time
import zenoh
role, ep, pfx, seconds, me, others, use_put = sys.argv[1:8]
c = zenoh.Config()
c.insert_json5("mode", '"peer"')
c.insert_json5("connect/endpoints", json.dumps([ep]))
c.insert_json5("listen/endpoints", '["tcp/127.0.0.1:0"]')
c.insert_json5("scouting/multicast/enabled", "false")
c.insert_json5("transport/link/tx/lease", "1000")
s = zenoh.open(c)
end = time.monotonic() + float(seconds)
topics = ("odom", "scan", "tf", "state")
if role == "pub":
    keys = [f"{pfx}/r{me}/{t}" for t in topics] + [f"{pfx}/world"]
    encs = [zenoh.Encoding("application/json").with_schema(k) for k in keys]
    pubs = [s.declare_publisher(k, encoding=e) for k, e in zip(keys, encs)]
    while time.monotonic() < end:
        for k, e, p in zip(keys, encs, pubs):
            s.put(k, b"{}", encoding=e) if use_put == "1" else p.put(b"{}")
        time.sleep(0.002)
    print("{}", flush=True)
    s.close()
else:
    bad, good = [], [0]
    def check(key):
        def cb(sample):
            schema = str(sample.encoding).split(";", 1)[-1]
            same = schema == key or (key.endswith("/world") and schema.endswith("/world"))
            if str(sample.key_expr) != key or not same:
                bad.append([key, schema])
            else:
                good[0] += 1
        return cb
    keys = [f"{pfx}/r{o}/{t}" for o in others.split(",") for t in topics] + [f"{pfx}/world"]
    subs = [s.declare_subscriber(k, check(k)) for k in keys]
    while time.monotonic() < end:
        time.sleep(0.2)
    time.sleep(1)
    print(json.dumps({"good": good[0], "bad": len(bad), "ex": bad[:3]}), flush=True)
s.close()
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--publishers", type=int, default=6)
    ap.add_argument("--put", action="store_true", help="session.put, no declared publishers")
    args = ap.parse_args()
    ep, pfx = f"tcp/127.0.0.1:{free_port()}", f"zm{os.getpid()}"
    router = subprocess.Popen([sys.executable, "-m", "zenros.router", "-l", ep],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(3)
    ids = [str(i) for i in range(1, args.publishers + 1)]

    def peer(role: str, me: str) -> subprocess.Popen[str]:
        return subprocess.Popen([sys.executable, "-c", PEER, role, ep, pfx, str(args.seconds),
                                 me, ",".join(ids), "1" if args.put else "0"],
                                stdout=subprocess.PIPE, text=True)

    pubs = [peer("pub", i) for i in ids]
    subs = [peer("sub", f"s{i}") for i in range(3)]
    try:
        time.sleep(8)
        stop_at = time.monotonic() + args.seconds - 15
        while time.monotonic() < stop_at:
            for group in ([p.pid for p in pubs], [subs[0].pid]):
                for pid in group:
                    os.kill(pid, signal.SIGSTOP)
                time.sleep(1.6)  # past the 1 s lease: the links drop
                for pid in group:
                    os.kill(pid, signal.SIGCONT)
                time.sleep(2)
        results = [json.loads(p.communicate(timeout=300)[0].strip() or "{}") for p in subs]
        for p in pubs:
            p.communicate(timeout=300)
    finally:
        for p in [*pubs, *subs]:
            if p.poll() is None:
                p.kill()
        router.send_signal(signal.SIGINT)
        router.wait(30)
    print(json.dumps({"bench": "zenoh_misrouting", "put": args.put,
                      "misrouted": sum(r.get("bad", 0) for r in results),
                      "received": sum(r.get("good", 0) for r in results),
                      "examples": [e for r in results for e in r.get("ex", [])][:3]}))


if __name__ == "__main__":
    main()
