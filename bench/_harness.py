"""Shared bench plumbing: loopback sessions, child processes, JSON output, stats."""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import zenoh
from zenros.testing import free_port, unique_prefix

__all__ = ["Child", "cpu_seconds", "emit", "env_info", "free_port", "missing_extra", "percentile", "raw_config",
           "unique_prefix"]


def missing_extra(err: ModuleNotFoundError, extra: str) -> str:
    """What a bench says when a reference it measures is not installed: the extra to add."""
    return (f"{sys.argv[0]}: the reference {err.name!r} is not installed; it comes with the "
            f"{extra!r} extra: pip install -e '.[{extra}]'")


def raw_config(listen: int | None = None, connect: int | None = None) -> zenoh.Config:
    """A raw zenoh peer config on loopback, multicast off (what zenros uses underneath)."""
    c = zenoh.Config()
    c.insert_json5("mode", '"peer"')
    c.insert_json5("listen/endpoints", json.dumps([f"tcp/127.0.0.1:{listen}"] if listen else []))
    c.insert_json5("connect/endpoints", json.dumps([f"tcp/127.0.0.1:{connect}"] if connect else []))
    c.insert_json5("scouting/multicast/enabled", "false")
    c.insert_json5("timestamping/enabled", "true")
    return c


def cpu_seconds(pid: int) -> float:
    """CPU seconds of one process's live threads, to the nanosecond (/proc schedstat), so
    that a nearly idle process still measures (clock ticks are 10 ms)."""
    total = 0
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            total += int((task / "schedstat").read_text().split()[0])
        except (OSError, IndexError, ValueError):  # a thread that ended meanwhile
            continue
    return total / 1e9


def percentile(xs: list[float], p: float) -> float:
    s = sorted(xs)
    return s[min(len(s) - 1, round(p / 100 * (len(s) - 1)))]


class Child:
    """A child process running ``script --role ...``; reads one JSON line as its result."""

    def __init__(self, script: str, *args: str) -> None:
        self.p = subprocess.Popen(
            [sys.executable, script, *args], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"},
        )
        assert self.p.stdout is not None
        line = self.p.stdout.readline()  # "ready", perhaps followed by what the child tells
        self.ready_line = line.strip()
        if not line.startswith("ready"):
            raise RuntimeError(f"child failed: {line}{self.p.stderr.read() if self.p.stderr else ''}")

    def result(self, timeout: float = 60) -> dict[str, Any]:
        assert self.p.stdout is not None
        out, err = self.p.communicate(timeout=timeout)
        for line in out.splitlines():
            if line.startswith("{"):
                r: dict[str, Any] = json.loads(line)
                return r
        raise RuntimeError(f"child gave no result: {out}\n{err}")

    def stop(self) -> None:
        if self.p.poll() is None and self.p.stdin is not None:
            self.p.stdin.close()  # children block on stdin; EOF tells them to finish
            try:
                self.p.wait(10)
            except subprocess.TimeoutExpired:
                pass
        if self.p.poll() is None:
            self.p.kill()
            self.p.wait()


def env_info() -> dict[str, Any]:
    return {
        "python": platform.python_version(),
        "machine": platform.machine(),
        "cpus": os.cpu_count(),
        "time": time.strftime("%Y-%m-%dT%H:%M:%S"),
    }


def emit(bench: str, metrics: dict[str, float], **extra: Any) -> None:
    """Print one JSON line: bench, then <metric>_zenros, <metric>_raw, <metric>_ratio."""
    print(json.dumps({"bench": bench, **metrics, **extra, "env": env_info()}), flush=True)


def median(xs: list[float]) -> float:
    return statistics.median(xs)


def paired_ratio(metric: dict[str, list[float]]) -> float:
    """The median of the per-repeat ``zenros / raw`` ratios: each repeat measures both back
    to back, so load that comes and goes on a shared machine hits both sides of a ratio."""
    return statistics.median(z / r for z, r in zip(metric["zenros"], metric["raw"], strict=True))


def latency_repeats(
    measure: Callable[[str], list[float]], repeats: int
) -> tuple[dict[str, list[float]], dict[str, list[float]]]:
    """p50 and p99 in microseconds of ``measure(impl)`` (seconds per call) for "raw" and
    "zenros", measured back to back in each of ``repeats`` repeats."""
    p50: dict[str, list[float]] = {"raw": [], "zenros": []}
    p99: dict[str, list[float]] = {"raw": [], "zenros": []}
    for _ in range(repeats):
        for impl in ("raw", "zenros"):
            xs = measure(impl)
            p50[impl].append(percentile(xs, 50) * 1e6)
            p99[impl].append(percentile(xs, 99) * 1e6)
    return p50, p99


def bench_parser(description: str | None, roles: Sequence[str], repeats: int) -> argparse.ArgumentParser:
    """The flags every two-process bench shares: the child's role, implementation, port and
    prefix, and how many back-to-back repeats the parent runs."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--role", choices=["parent", *roles], default="parent")
    ap.add_argument("--impl", default="zenros")
    ap.add_argument("--port", type=int, default=0)
    ap.add_argument("--prefix", default="bench")
    ap.add_argument("--repeats", type=int, default=repeats)
    return ap


def serve_node(port: int, prefix: str, name: str, setup: Callable[[Any], Any]) -> None:
    """A child's zenros side: a node connected to the parent, set up, serving until the
    parent closes our stdin (`Child.stop`)."""
    from zenros.context import Context
    from zenros.node import Node
    from zenros.testing import loopback_options

    ctx = Context(loopback_options(connect=[port]), prefix=prefix)
    node = Node(name, context=ctx)
    try:
        setup(node)
        print("ready", flush=True)
        sys.stdin.readline()
    finally:
        node.close()
        ctx.close()
