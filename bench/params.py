"""Parameter server benchmark: get/set latency (p50) and set throughput, zenros vs raw zenoh.

Two processes on loopback, multicast off. The child serves: either the real master
(`MasterNode`, SQLite with fsync, in a temporary data dir) or a raw zenoh queryable that
answers the same key with the same JSON value (and, for "set", acknowledges a payload
without storing it). The parent reads with `ParameterClient.get` (one zenoh get on the
parameter's key, JSON decode) against a raw `session.get` plus JSON decode. Sets are
sequential acknowledged writes (each durable on the master's disk before the answer).
Both pairs run at once and the parent alternates between them in blocks, so load from other
processes on the machine hits both alike. Prints one JSON line.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Callable

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
        master.store.set(NAME, VALUE)
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

Call = Callable[[], object]
Put = Callable[[int], object]
BLOCK = 100


class Pair:
    """Both servers and both clients at once, so gets can alternate between them."""

    def __init__(self) -> None:
        zport, rport = free_port(), free_port()
        zprefix, rprefix = unique_prefix(), unique_prefix()
        self.ctx = Context(loopback_options(zport), prefix=zprefix)
        self.raw = zenoh.open(raw_config(listen=rport))
        self.children = [
            Child(__file__, "--role", "child", "--impl", "zenros", "--port", str(zport),
                  "--prefix", zprefix),
            Child(__file__, "--role", "child", "--impl", "raw", "--port", str(rport),
                  "--prefix", rprefix),
        ]
        client = ParameterClient(self.ctx)
        assert client.wait_for_master(10)
        self.zenros_get: Call = lambda: client.get(NAME)
        self.zenros_set: Put = lambda i: client.set("/bench/n", i)
        key, set_key = f"{rprefix}/param{NAME}", f"{rprefix}/raw_set"
        self.raw_get: Call = lambda: self._query(key, None)
        self.raw_set: Put = lambda i: self._query(set_key, msgspec.json.encode(i))
        deadline = time.monotonic() + 10
        while True:  # until the raw queryable is routed
            try:
                self.raw_get()
                break
            except RuntimeError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.01)

    def _query(self, key: str, payload: bytes | None) -> object:
        for reply in self.raw.get(key, payload=payload, timeout=5):
            if reply.ok is not None:
                return msgspec.json.decode(reply.ok.payload.to_bytes())
        raise RuntimeError(f"no reply on {key}")

    def close(self) -> None:
        for c in self.children:
            c.stop()
        self.ctx.close()
        self.raw.close()


def _timed(fn: Callable[[int], object], n: int, out: list[float]) -> float:
    start = time.perf_counter()
    for i in range(n):
        t0 = time.perf_counter()
        fn(i)
        out.append(time.perf_counter() - t0)
    return time.perf_counter() - start


def run(gets: int, sets: int) -> dict[str, tuple[list[float], list[float], float]]:
    """Per implementation: get latencies, set latencies (s) and set throughput (1/s).

    Raw and zenros run in alternating blocks of `BLOCK` calls, so load from elsewhere on
    the machine hits both alike.
    """
    pair = Pair()
    try:
        impls: dict[str, tuple[Call, Put]] = {
            "raw": (pair.raw_get, pair.raw_set), "zenros": (pair.zenros_get, pair.zenros_set)}
        lat_get: dict[str, list[float]] = {i: [] for i in impls}
        lat_set: dict[str, list[float]] = {i: [] for i in impls}
        busy: dict[str, float] = {i: 0.0 for i in impls}
        for get, put in impls.values():  # warm-up
            for i in range(200):
                get()
            for i in range(20):
                put(i)
        for _ in range(max(1, gets // BLOCK)):
            for name, (get, _) in impls.items():
                _timed(lambda i, g=get: g(), BLOCK, lat_get[name])
        for _ in range(max(1, sets // BLOCK)):
            for name, (_, put) in impls.items():
                busy[name] += _timed(put, BLOCK, lat_set[name])
        return {i: (lat_get[i], lat_set[i], len(lat_set[i]) / busy[i]) for i in impls}
    finally:
        pair.close()


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
    for _ in range(a.repeats):
        for impl, (g, s, t) in run(a.gets, a.sets).items():
            get50[impl].append(percentile(g, 50) * 1e6)
            set50[impl].append(percentile(s, 50) * 1e6)
            thr[impl].append(t)
    gz, gr = statistics.median(get50["zenros"]), statistics.median(get50["raw"])
    emit(
        "params",
        {
            "get_p50_us_zenros": round(gz, 1), "get_p50_us_raw": round(gr, 1),
            "get_p50_ratio": round(gz / gr, 3),
            "set_p50_us_zenros": round(statistics.median(set50["zenros"]), 1),
            "set_p50_us_raw": round(statistics.median(set50["raw"]), 1),
            "set_throughput_zenros": round(statistics.median(thr["zenros"])),
            "set_throughput_raw": round(statistics.median(thr["raw"])),
        },
        value="float 0.5 (JSON)", set_durability="SQLite WAL, synchronous=FULL (fsync per set)",
        set_raw="query with payload, acknowledged, not stored",
        stat=f"median over repeats of each run's p50; raw and zenros alternate in blocks of"
             f" {BLOCK} calls", gets=a.gets, sets=a.sets, repeats=a.repeats,
    )


if __name__ == "__main__":
    main()
