"""Parameter server benchmark: get/set latency (p50) and set throughput, zenros vs raw zenoh.

Two processes on loopback, multicast off. The child serves: either the real master
(`MasterNode`, SQLite with fsync, in a temporary data dir) or a raw zenoh queryable that
answers the same key with the same JSON value (and, for "set", acknowledges a payload
without storing it). The parent reads with `ParameterClient.get` (one zenoh get on the
parameter's key, JSON decode) against a raw `session.get` plus JSON decode. Sets are
sequential acknowledged writes (each durable on the master's disk before the answer).
Prints one JSON line.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time

import msgspec
import zenoh

from _harness import Child, emit, free_port, percentile, raw_config, unique_prefix
from zenros.context import Context
from zenros.param_client import ParameterClient
from zenros.services.master.node import MasterNode
from zenros.testing import loopback_options

VALUE = 0.5
NAME = "/bench/value"


# ------------------------------------------------------------------ children


def child(impl: str, port: int, prefix: str) -> None:
    if impl == "zenros":
        home = tempfile.mkdtemp(prefix="zenros-bench-")
        ctx = Context(loopback_options(connect=[port]), prefix=prefix)
        master = MasterNode(context=ctx, parameter_overrides={"data_dir": home,
                                                               "sync_period": 0.0})
        print("ready", flush=True)
        sys.stdin.readline()
        master.close()
        ctx.close()
        shutil.rmtree(home, ignore_errors=True)
        return
    s = zenoh.open(raw_config(connect=port))
    data = msgspec.json.encode(VALUE)

    def on_get(query: zenoh.Query) -> None:
        with query:
            query.reply(query.key_expr, data, encoding="application/json")

    def on_set(query: zenoh.Query) -> None:
        with query:
            payload = query.payload
            msgspec.json.decode(payload.to_bytes() if payload is not None else b"0")
            query.reply(query.key_expr, b"{}", encoding="application/json")

    getter = s.declare_queryable(f"{prefix}/param{NAME}", on_get, complete=True)
    setter = s.declare_queryable(f"{prefix}/raw_set", on_set, complete=True)
    print("ready", flush=True)
    sys.stdin.readline()
    getter.undeclare()
    setter.undeclare()
    s.close()


# ------------------------------------------------------------------ parent


def run(impl: str, gets: int, sets: int) -> tuple[list[float], list[float], float]:
    """Latencies (s) of ``gets`` gets and ``sets`` sets, and the set throughput (1/s)."""
    port, prefix = free_port(), unique_prefix()
    if impl == "zenros":
        ctx = Context(loopback_options(port), prefix=prefix)
        proc = Child(__file__, "--role", "child", "--impl", impl, "--port", str(port),
                     "--prefix", prefix)
        client = ParameterClient(ctx)
        try:
            assert client.wait_for_master(10)
            client.set(NAME, VALUE)
            get = lambda: client.get(NAME)  # noqa: E731
            put = lambda i: client.set("/bench/n", i)  # noqa: E731
            return _measure(get, put, gets, sets)
        finally:
            proc.stop()
            ctx.close()
    s = zenoh.open(raw_config(listen=port))
    proc = Child(__file__, "--role", "child", "--impl", impl, "--port", str(port),
                 "--prefix", prefix)
    key, set_key = f"{prefix}/param{NAME}", f"{prefix}/raw_set"

    def raw_get() -> object:
        for reply in s.get(key, timeout=5):
            if reply.ok is not None:
                return msgspec.json.decode(reply.ok.payload.to_bytes())
        raise RuntimeError("no reply")

    def raw_set(i: int) -> object:
        for reply in s.get(set_key, payload=msgspec.json.encode(i), timeout=5):
            if reply.ok is not None:
                return msgspec.json.decode(reply.ok.payload.to_bytes())
        raise RuntimeError("no reply")

    try:
        deadline = time.monotonic() + 10
        while True:  # until the queryable is routed
            try:
                raw_get()
                break
            except RuntimeError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.01)
        return _measure(raw_get, raw_set, gets, sets)
    finally:
        proc.stop()
        s.close()


def _measure(get: object, put: object, gets: int, sets: int) -> tuple[list[float], list[float],
                                                                     float]:
    assert callable(get) and callable(put)
    for _ in range(200):
        get()
    lat_get = []
    for _ in range(gets):
        t0 = time.perf_counter()
        get()
        lat_get.append(time.perf_counter() - t0)
    for i in range(20):
        put(i)
    lat_set = []
    start = time.perf_counter()
    for i in range(sets):
        t0 = time.perf_counter()
        put(i)
        lat_set.append(time.perf_counter() - t0)
    total = time.perf_counter() - start
    return lat_get, lat_set, sets / total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--role", choices=["parent", "child"], default="parent")
    ap.add_argument("--impl", default="zenros")
    ap.add_argument("--port", type=int, default=0)
    ap.add_argument("--prefix", default="bench")
    ap.add_argument("--gets", type=int, default=2000)
    ap.add_argument("--sets", type=int, default=500)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    if a.role == "child":
        child(a.impl, a.port, a.prefix)
        return
    impls = ("raw", "zenros")
    get50: dict[str, list[float]] = {i: [] for i in impls}
    set50: dict[str, list[float]] = {i: [] for i in impls}
    thr: dict[str, list[float]] = {i: [] for i in impls}
    for _ in range(a.repeats):  # interleaved, so drift on a noisy machine hits both
        for impl in impls:
            g, s, t = run(impl, a.gets, a.sets)
            get50[impl].append(percentile(g, 50) * 1e6)
            set50[impl].append(percentile(s, 50) * 1e6)
            thr[impl].append(t)
    gz, gr = min(get50["zenros"]), min(get50["raw"])
    emit(
        "params",
        {
            "get_p50_us_zenros": round(gz, 1), "get_p50_us_raw": round(gr, 1),
            "get_p50_ratio": round(gz / gr, 3),
            "set_p50_us_zenros": round(min(set50["zenros"]), 1),
            "set_p50_us_raw": round(min(set50["raw"]), 1),
            "set_throughput_zenros": round(max(thr["zenros"])),
            "set_throughput_raw": round(max(thr["raw"])),
        },
        value="float 0.5 (JSON)", set_durability="SQLite WAL, synchronous=FULL (fsync per set)",
        set_raw="query with payload, acknowledged, not stored", gets=a.gets, sets=a.sets,
        repeats=a.repeats,
    )


if __name__ == "__main__":
    main()
